"""TDEV and MTIE masks of the ITU-T recommendations for reference clocks,
under AllanTools 2024.6's names: PRC (G.811, Amendment 1, 2016), PRTC-A
and PRTC-B (G.8272, 11/2018, Tables 1-4) and ePRTC (G.8272.1, Amendment 1,
2017, Tables 1-2). Each takes tau in seconds and returns the limit in
seconds; the mask's range of validity is not checked, as in AllanTools."""


def _flat_ramp_flat(tau, low, start, slope, end, high):
    """The TDEV masks' shape: ``low`` below ``start`` s, ``slope`` tau below
    ``end`` s, ``high`` after."""
    if tau < start:
        return low
    if tau < end:
        return slope * tau
    return high


def _g811_mtie_line(tau):
    """(0.275e-3 tau + 0.025) us, the MTIE line G.811 and G.8272 share."""
    return 1e-6 * (0.275e-3 * tau + 0.025)


def prc_tdev(tau):
    """G.811 PRC TDEV: 3 ns to 100 s, 0.03 tau ns to 1000 s, 30 ns after."""
    return _flat_ramp_flat(tau, 3e-9, 100, 0.03e-9, 1000, 30e-9)


def prc_mtie(tau):
    """G.811 PRC MTIE: (0.275e-3 tau + 0.025) us to 1000 s, then
    (1e-5 tau + 0.29) us."""
    if tau < 1000:
        return _g811_mtie_line(tau)
    return 1e-6 * (1e-5 * tau + 0.29)


def eprtc_tdev(tau):
    """G.8272.1 ePRTC TDEV (Table 2): 1 ns to 30 000 s, then rising as
    tau / 30 000 ns to 10 ns at 300 000 s."""
    return _flat_ramp_flat(tau, 1e-9, 30e3, 3.33333e-5 * 1e-9, 300e3, 10e-9)


def eprtc_mtie(tau):
    """G.8272.1 ePRTC MTIE (Table 1): 4 ns to 1 s, (0.11114 tau + 3.89) ns to
    100 s, (0.0375e-3 tau + 15) ns to 400 000 s, 30 ns after."""
    if tau <= 1:
        return 4e-9
    if tau <= 100:
        return 1e-9 * (0.11114 * tau + 3.89)
    if tau <= 400e3:
        return 1e-9 * (0.0375e-3 * tau + 15.0)
    return 30e-9


def prtcA_tdev(tau):
    """G.8272 PRTC-A TDEV (Table 3): 3 ns to 100 s, 0.03 tau ns to 1000 s,
    30 ns after."""
    return _flat_ramp_flat(tau, 3e-9, 100, 0.03e-9, 1000, 30e-9)


def prtcB_tdev(tau):
    """G.8272 PRTC-B TDEV (Table 4): 1 ns to 100 s, 0.01 tau ns to 500 s,
    5 ns after."""
    return _flat_ramp_flat(tau, 1e-9, 100, 0.01e-9, 500, 5e-9)


def prtcA_mtie(tau):
    """G.8272 PRTC-A MTIE (Table 1): (0.275e-3 tau + 0.025) us to 273 s,
    100 ns after."""
    if tau < 273:
        return _g811_mtie_line(tau)
    return 100e-9


def prtcB_mtie(tau):
    """G.8272 PRTC-B MTIE (Table 2): (0.275e-3 tau + 0.025) us to 54.5 s,
    40 ns after."""
    if tau < 54.5:
        return _g811_mtie_line(tau)
    return 40e-9
