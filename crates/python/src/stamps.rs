//! Where each time stamp of a recording sits on its sample clock.
//!
//! A reader that finds a time column places the rows one slot after another
//! on the clock (`imu::timing::regularize`), leaving the slots of a time
//! gap empty and dropping a row that repeats the previous one, stamp and
//! values. The recording keeps one stamp per row read; a table indexed by
//! the clock (`Recording.to_pandas()`) needs each stamp's slot. The rule is
//! `regularize`'s, replayed on the stamps alone.

use imu::timing::GAP_FACTOR;

/// The slot of every stamp (-1 for a row the reader dropped), or `None`
/// when the placement cannot be replayed from the stamps alone: some but
/// not all of the rows that repeat the previous stamp were dropped (which
/// ones depends on values no longer held), or the replay does not land on
/// the `slots` the channels have.
pub fn stamp_slots(t: &[f64], rate_hz: Option<f64>, slots: usize, dropped: usize) -> Option<Vec<i64>> {
    let identity = || (0..t.len() as i64).collect::<Vec<_>>();
    let repeats = (1..t.len())
        .filter(|&i| t[i].is_finite() && t[i - 1] == t[i])
        .count();
    if dropped == 0 && t.len() == slots {
        // Rows one per slot: every step below the gap factor (or no clock
        // was fitted and the rows were kept as read).
        return Some(identity());
    }
    let rate = rate_hz.filter(|r| r.is_finite() && *r > 0.0)?;
    if !t.iter().any(|v| v.is_finite()) {
        return (t.len() == slots && dropped == 0).then(identity);
    }
    let drop_repeats = match dropped {
        0 => false,
        d if d == repeats => true,
        _ => return None,
    };
    let period = 1.0 / rate;
    let mut out = Vec::with_capacity(t.len());
    // (slot, row) of the latest well-stamped row, and the latest slot used.
    let mut last: Option<(usize, usize)> = None;
    let mut used: Option<usize> = None;
    for (i, &ti) in t.iter().enumerate() {
        if drop_repeats && i > 0 && ti.is_finite() && t[i - 1] == ti {
            out.push(-1);
            continue;
        }
        let next = used.map_or(0, |u| u + 1);
        let slot = match (last, used) {
            (Some((s, r)), Some(_)) if ti.is_finite() => {
                let d = ti - t[r];
                let step = (d * rate).round();
                if d > GAP_FACTOR * period && step.is_finite() {
                    (s as f64 + step).max(next as f64) as usize
                } else {
                    next
                }
            }
            _ => next,
        };
        if slot >= slots {
            return None;
        }
        if ti.is_finite() && last.is_none_or(|(_, r)| ti > t[r]) {
            last = Some((slot, i));
        }
        used = Some(slot);
        out.push(slot as i64);
    }
    (used.map_or(0, |u| u + 1) == slots).then_some(out)
}
