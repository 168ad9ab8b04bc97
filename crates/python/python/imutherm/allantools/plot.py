"""A log-log plot of a :class:`Dataset`, under AllanTools 2024.6's name
``Plot``. Needs matplotlib (``pip install matplotlib``): without it
``Plot()`` raises ``RuntimeError``, as in AllanTools."""


class Plot:
    """A figure with log-log axes (``fig``, ``ax``; ``plt`` is
    matplotlib.pyplot). ``no_display`` selects the Agg backend (no
    window)."""

    def __init__(self, no_display=False):
        try:
            import matplotlib
            if no_display:
                matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            raise RuntimeError("Plot needs matplotlib: pip install matplotlib") from None
        self.plt = plt
        self.fig, self.ax = plt.subplots()
        self.ax.set_xscale("log")
        self.ax.set_yscale("log")

    def plot(self, atDataset, errorbars=False, grid=False, **kwargs):
        """Plots the computed statistic of ``atDataset`` against tau, with
        its error bars if asked; ``kwargs`` go to matplotlib."""
        out = atDataset.out
        if errorbars:
            self.ax.errorbar(out["taus"], out["stat"], yerr=out["stat_err"], **kwargs)
        else:
            self.ax.plot(out["taus"], out["stat"], **kwargs)
        self.ax.set_xlabel("Tau")
        self.ax.set_ylabel(out["stat_id"])
        if grid:
            self.ax.grid(True, which="minor", ls="-", color="0.65")
            self.ax.grid(True, which="major", ls="-", color="0.25")
        else:
            self.ax.grid(False)

    def show(self):
        """Shows the figure."""
        self.plt.show()

    def save(self, f):
        """Saves the figure to ``f``."""
        self.plt.savefig(f)
