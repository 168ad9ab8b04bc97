//! The bias of a real sensor over a thermal history: a polynomial of the
//! element's temperature (the logged one through a first-order lag τ) plus
//! a hysteresis that follows the direction of change, saturates, and
//! relaxes: `(a0 + a1·u + a2·u²)·d`, d the element's rate r (over
//! [`RATE_SMOOTHING_S`]) saturated as tanh(r/s) and then passed through a
//! first-order lag of τ_d (the direction's memory: a plateau after a climb
//! fades the term over τ_d, a reversal swings it over τ_d).
//!
//! The relaxation comes after the saturation because that is what a
//! direction memory does: smoothing the rate first and saturating after
//! (the form of earlier models, still applied as written where a model
//! holds it) keeps the term at full strength until the smoothed rate has
//! fallen almost to zero, then switches it; on a climb that stops at a
//! plateau it misses the fade, and on held-out runs at other rates it left
//! 2–12× the floor where the true lag was known.
//!
//! Where heating and cooling disagree, no polynomial of the logged
//! temperature explains both branches, so a cross-validation over
//! polynomials alone picks a low order and underfits. Here every
//! structure — the lag (τ on a grid, then refined), the hysteresis (its
//! rate scale s on a grid, its amplitude constant or linear in T) and the
//! order — is scored on held-out cells (leave one run out, or blocks of one
//! run's cells in time), and a term enters only where the held-out error
//! falls by more than one standard error of the difference (the smallest
//! structure within one standard error of the best wins). Cells are keyed
//! by the logged temperature and direction whatever τ, so that every
//! structure is scored on the same cells and the differences pair.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::branch;
use crate::element;
use crate::hysteresis::BranchResidual;
use crate::tcal::Run;
use crate::weights;

/// Lags tried, s (besides none): about ×1.5 apart from a quarter minute to
/// seven minutes, the range of packaged MEMS on boards.
pub const LAG_GRID_S: [f64; 9] = [15.0, 25.0, 40.0, 60.0, 90.0, 130.0, 190.0, 280.0, 400.0];
/// Rate scales of the hysteresis's saturation, °C/s: from a switch at a
/// twentieth of a °C/min (direction alone) to a term nearly linear in the
/// rate up to a few °C/min.
pub const RATE_SCALES_C_PER_S: [f64; 4] = [0.05 / 60.0, 0.25 / 60.0, 1.0 / 60.0, 5.0 / 60.0];
/// The smoothing of the element's rate before it is saturated, s: short
/// against the direction's memory, long enough that the temperature's
/// noise and readout steps do not switch the direction.
pub const RATE_SMOOTHING_S: f64 = 30.0;
/// Relaxation times of the direction's memory tried, s.
pub const DIRECTION_GRID_S: [f64; 4] = [40.0, 80.0, 160.0, 320.0];
/// Amplitude terms of a hysteresis: 1, u, u² (a hysteresis that is a shift
/// of the element's temperature is worth p'(T) times it, and p' of a cubic
/// is a quadratic).
const AMP: usize = 3;
/// Smoothing and rate scale pairs.
const NCOMBO: usize = DIRECTION_GRID_S.len() * RATE_SCALES_C_PER_S.len();
/// Regressors: per pair, tanh(r/s)·u^j, j < AMP.
const NREG: usize = AMP * NCOMBO;

fn combo(c: usize) -> (f64, f64) {
    (
        DIRECTION_GRID_S[c / RATE_SCALES_C_PER_S.len()],
        RATE_SCALES_C_PER_S[c % RATE_SCALES_C_PER_S.len()],
    )
}
/// The smaller direction's least share of the samples for a hysteresis
/// to be tried.
pub const MIN_BRANCH_SHARE: f64 = 0.1;
/// Time constants the longest run must span for a lag to be tried.
pub const MIN_RUN_LAGS: f64 = 5.0;
/// Time either side of a held-out cell whose cells do not train, s.
pub const GUARD_S: f64 = 300.0;
/// χ²(1)'s 95th percentile: the profile's rise that bounds a 95 % interval.
const CHI2_1_95: f64 = 3.841_458_820_694_124;

/// The hysteresis term of a channel: `(Σ c_j·u^j)·tanh(r/s)` added to the
/// bias, r the element temperature's rate smoothed through a first-order
/// lag of `smoothing_s`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HysteresisTerm {
    /// Amplitude in u = (T − centre)/scale, ascending powers (the heating
    /// branch reads twice it above the cooling one, saturated).
    pub coefficients: Vec<f64>,
    /// Rate at which the term reaches tanh(1) of its amplitude, °C/s.
    pub rate_scale_c_per_s: f64,
    /// Time constant of the rate's smoothing, s.
    pub smoothing_s: f64,
    /// Time constant of the saturated direction's relaxation, s; absent
    /// in models that smoothed the rate over `smoothing_s` alone and then
    /// saturated it (they apply as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relax_s: Option<f64>,
    /// Heating minus cooling at the range's centre, saturated, in the
    /// channel's unit.
    pub heating_minus_cooling: f64,
    /// Its 95 % interval.
    pub interval_95: [f64; 2],
}

impl HysteresisTerm {
    /// The term at scaled temperature `u` and a steady rate `r` (°C/s),
    /// where the direction has settled.
    pub fn at(&self, u: f64, r: f64) -> f64 {
        self.amplitude(u) * (r / self.rate_scale_c_per_s).tanh()
    }

    /// The amplitude at scaled temperature `u`: the term where the
    /// direction is fully heating.
    pub fn amplitude(&self, u: f64) -> f64 {
        self.coefficients.iter().rev().fold(0.0, |acc, c| acc * u + c)
    }

    /// The direction, −1 to 1, at each sample of the element's
    /// temperature `element_t`; NaN where it is.
    pub fn direction(&self, element_t: &[f64], rate_hz: f64) -> Vec<f64> {
        direction(
            element_t,
            rate_hz,
            self.smoothing_s,
            self.rate_scale_c_per_s,
            self.relax_s,
        )
    }
}

/// The element's rate over `smoothing_s` saturated at `scale` (°C/s), and
/// then relaxed over `relax_s` where given; NaN where the temperature is.
pub fn direction(
    element_t: &[f64],
    rate_hz: f64,
    smoothing_s: f64,
    scale: f64,
    relax_s: Option<f64>,
) -> Vec<f64> {
    let sat: Vec<f64> = element::smoothed_rate(element_t, rate_hz, smoothing_s)
        .iter()
        .map(|r| (r / scale).tanh())
        .collect();
    match relax_s {
        Some(t) => element::lag(&sat, rate_hz, t),
        None => sat,
    }
}

/// What the search found for one channel, where it beat the polynomial of
/// the logged temperature alone.
#[derive(Debug, Clone)]
pub(crate) struct Found {
    pub lag_s: Option<f64>,
    pub lag_interval_s: Option<[f64; 2]>,
    pub order: usize,
    pub coefficients: Vec<f64>,
    pub hysteresis: Option<HysteresisTerm>,
    pub residual_rms: f64,
    pub residual_max: f64,
    pub cross_validation: Vec<(usize, f64)>,
    pub branches: Vec<BranchResidual>,
}

/// The frame the search works in.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub centre: f64,
    pub scale: f64,
    pub width: f64,
    pub t_min: f64,
    pub t_max: f64,
    /// Orders tried.
    pub orders: (usize, usize),
}

/// One cell: the samples of one run, one logged-temperature bin and one
/// direction, kept as mean products so the fit is least squares over its
/// samples.
#[derive(Clone)]
struct Cell {
    key: i64,
    heating: bool,
    run: usize,
    first: usize,
    /// Times of its first and last samples, s.
    span_s: [f64; 2],
    n: f64,
    t: f64,
    /// Mean u^j, j ≤ 2·powers.
    pw: Vec<f64>,
    /// Mean g_a·u^j, j ≤ powers.
    ru: Vec<Vec<f64>>,
    /// Mean g_a·g_b, b within a's pair (b's index modulo AMP).
    rr: Vec<Vec<f64>>,
    /// Per channel: mean x·u^j, mean x·g_a, mean x.
    xu: Vec<Vec<f64>>,
    xr: Vec<Vec<f64>>,
    x: Vec<f64>,
}

/// A structure: lag index (0: none, else LAG_GRID_S[i − 1] or a refined
/// value), order, and the regressors it uses.
#[derive(Debug, Clone, PartialEq)]
struct Structure {
    order: usize,
    regs: Vec<usize>,
}

fn plain(order: usize) -> Structure {
    Structure { order, regs: vec![] }
}

fn hysteretic(order: usize, c: usize, amp: usize) -> Structure {
    Structure {
        order,
        regs: (0..amp).map(|j| AMP * c + j).collect(),
    }
}

fn usable(run: &Run, i: usize) -> bool {
    run.temp[i].is_finite() && run.channels.iter().all(|c| c.data[i].is_finite())
}

/// The cells of every run at lag `tau` (0: none).
fn cells(runs: &[Run], tau: f64, f: &Frame) -> Vec<Cell> {
    use std::collections::BTreeMap;
    let powers = f.orders.1;
    let mut out = Vec::new();
    for (ri, run) in runs.iter().enumerate() {
        let teff = element::lag(run.temp, run.rate_hz, tau);
        let dirs: Vec<Vec<f64>> = (0..NCOMBO)
            .map(|c| {
                let (relax, scale) = combo(c);
                direction(&teff, run.rate_hz, RATE_SMOOTHING_S, scale, Some(relax))
            })
            .collect();
        let heating = branch::heating(run.temp, run.rate_hz);
        let nch = run.channels.len();
        let mut acc: BTreeMap<(i64, bool), Cell> = BTreeMap::new();
        let mut g = [0.0; NREG];
        let mut up = vec![0.0; 2 * powers + 1];
        for i in 0..run.temp.len() {
            if !usable(run, i) {
                continue;
            }
            let key = ((run.temp[i] / f.width).floor() as i64, heating[i]);
            let c = acc.entry(key).or_insert_with(|| Cell {
                key: key.0,
                heating: key.1,
                run: ri,
                first: i,
                span_s: [i as f64 / run.rate_hz; 2],
                n: 0.0,
                t: 0.0,
                pw: vec![0.0; 2 * powers + 1],
                ru: vec![vec![0.0; powers + 1]; NREG],
                rr: vec![vec![0.0; AMP]; NREG],
                xu: vec![vec![0.0; powers + 1]; nch],
                xr: vec![vec![0.0; NREG]; nch],
                x: vec![0.0; nch],
            });
            let u = (teff[i].clamp(f.t_min, f.t_max) - f.centre) / f.scale;
            let mut p = 1.0;
            for v in up.iter_mut() {
                *v = p;
                p *= u;
            }
            for (c, d) in dirs.iter().enumerate() {
                let mut v = if d[i].is_finite() { d[i] } else { 0.0 };
                for j in 0..AMP {
                    g[AMP * c + j] = v;
                    v *= u;
                }
            }
            c.n += 1.0;
            c.t += run.temp[i];
            c.span_s[1] = i as f64 / run.rate_hz;
            for (a, b) in c.pw.iter_mut().zip(&up) {
                *a += b;
            }
            for a in 0..NREG {
                for (s, b) in c.ru[a].iter_mut().zip(&up) {
                    *s += g[a] * b;
                }
                let base = a - a % AMP;
                for b in 0..AMP {
                    c.rr[a][b] += g[a] * g[base + b];
                }
            }
            for (k, ch) in run.channels.iter().enumerate() {
                let x = ch.data[i];
                c.x[k] += x;
                for (s, b) in c.xu[k].iter_mut().zip(&up) {
                    *s += x * b;
                }
                for (s, ga) in c.xr[k].iter_mut().zip(&g) {
                    *s += x * ga;
                }
            }
        }
        for (_, mut c) in acc {
            let n = c.n;
            c.t /= n;
            let div = |v: &mut Vec<f64>| v.iter_mut().for_each(|x| *x /= n);
            div(&mut c.pw);
            c.ru.iter_mut().for_each(div);
            c.rr.iter_mut().for_each(div);
            c.xu.iter_mut().for_each(div);
            c.xr.iter_mut().for_each(div);
            div(&mut c.x);
            out.push(c);
        }
    }
    out
}

/// Weighted least squares of channel `k` on the structure over `idx`;
/// with the normal matrix's inverse (unit-diagonal scaled pseudo-inverse).
fn solve(
    cells: &[Cell],
    idx: &[usize],
    w: &[f64],
    k: usize,
    s: &Structure,
) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let o = s.order + 1;
    let cols = o + s.regs.len();
    if idx.len() < cols {
        return None;
    }
    let mut a = DMatrix::<f64>::zeros(cols, cols);
    let mut y = DVector::<f64>::zeros(cols);
    for &ci in idx {
        let c = &cells[ci];
        let wc = w[ci];
        for i in 0..cols {
            for j in i..cols {
                let v = match (i < o, j < o) {
                    (true, true) => c.pw[i + j],
                    (true, false) => c.ru[s.regs[j - o]][i],
                    (false, true) => c.ru[s.regs[i - o]][j],
                    (false, false) => c.rr[s.regs[i - o]][s.regs[j - o] % AMP],
                };
                a[(i, j)] += wc * v;
            }
            y[i] += wc * if i < o { c.xu[k][i] } else { c.xr[k][s.regs[i - o]] };
        }
    }
    for i in 0..cols {
        for j in 0..i {
            a[(i, j)] = a[(j, i)];
        }
    }
    let (sol, inv) = normal_solve(&a, &y, true)?;
    Some((sol, inv?))
}

/// The normal equations `a·x = y` solved with each column scaled to a unit
/// diagonal (the columns' sizes differ by orders), by a pseudo-inverse that
/// drops what the data cannot determine; with the inverse of `a` where
/// asked (for the coefficients' covariance).
pub(crate) fn normal_solve(
    a: &DMatrix<f64>,
    y: &DVector<f64>,
    inverse: bool,
) -> Option<(Vec<f64>, Option<DMatrix<f64>>)> {
    let cols = a.nrows();
    let d: Vec<f64> = (0..cols).map(|i| a[(i, i)].sqrt()).collect();
    if d.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return None;
    }
    let scaled = DMatrix::from_fn(cols, cols, |i, j| a[(i, j)] / (d[i] * d[j]));
    let rhs = DVector::from_fn(cols, |i, _| y[i] / d[i]);
    let svd = scaled.svd(true, true);
    let top = svd.singular_values.max();
    let sol = svd.solve(&rhs, top * 1e-13).ok()?;
    let inv = if inverse {
        let p = svd.pseudo_inverse(top * 1e-13).ok()?;
        Some(DMatrix::from_fn(cols, cols, |i, j| p[(i, j)] / (d[i] * d[j])))
    } else {
        None
    };
    let sol: Vec<f64> = sol.iter().zip(&d).map(|(v, d)| v / d).collect();
    sol.iter().all(|v| v.is_finite()).then_some((sol, inv))
}

fn predict(c: &Cell, s: &Structure, coef: &[f64]) -> f64 {
    let o = s.order + 1;
    let p: f64 = coef[..o].iter().zip(&c.pw).map(|(a, b)| a * b).sum();
    let h: f64 = coef[o..].iter().zip(&s.regs).map(|(a, &r)| a * c.ru[r][0]).sum();
    p + h
}

/// Folds: blocks of about a tenth of each run's cells in time, dealt
/// round-robin to five folds over all the runs; the cells at the range's
/// ends always train. Never one run left out: with a heating run and a
/// cooling one, each alone has one direction, and a hysteresis learnt on
/// neither could not be judged.
fn folds(cells: &[Cell], runs: usize, f: &Frame) -> (usize, Vec<Option<usize>>) {
    let key = |t: f64| (t / f.width).floor() as i64;
    let edge = |c: &Cell| c.key == key(f.t_min) || c.key == key(f.t_max);
    let mut fold = vec![None; cells.len()];
    let mut dealt = 0usize;
    for run in 0..runs {
        let mut order: Vec<usize> = (0..cells.len()).filter(|&i| cells[i].run == run).collect();
        order.sort_by_key(|&i| cells[i].first);
        let block = order.len().div_ceil(10).max(1);
        for (pos, &i) in order.iter().enumerate() {
            fold[i] = (!edge(&cells[i])).then_some((dealt + pos / block) % 5);
        }
        dealt += order.len().div_ceil(block);
    }
    (5, fold)
}

/// Each held-out cell's w·e², NaN for cells never held out; `None` where a
/// fold cannot be fitted.
fn held_out(
    cells: &[Cell],
    w: &[f64],
    k: usize,
    s: &Structure,
    nf: usize,
    fold: &[Option<usize>],
) -> Option<Vec<f64>> {
    let mut sq = vec![f64::NAN; cells.len()];
    for f in 0..nf {
        let test: Vec<usize> = (0..cells.len()).filter(|&i| fold[i] == Some(f)).collect();
        if test.is_empty() {
            continue;
        }
        // Cells within the guard of a held-out one in the same run never
        // train: the bias wanders (bias instability, minutes), and a
        // neighbour in time would carry the held-out cell's wander into the
        // fit, which terms that follow time (the direction) then learn.
        let near = |i: usize| {
            test.iter().any(|&t| {
                let (a, b) = (&cells[i], &cells[t]);
                a.run == b.run && a.span_s[0] - GUARD_S <= b.span_s[1] && b.span_s[0] - GUARD_S <= a.span_s[1]
            })
        };
        let train: Vec<usize> = (0..cells.len())
            .filter(|&i| fold[i] != Some(f) && (fold[i].is_none() || !near(i)))
            .collect();
        let (coef, _) = solve(cells, &train, w, k, s)?;
        for i in test {
            let e = cells[i].x[k] - predict(&cells[i], s, &coef);
            sq[i] = w[i] * e * e;
        }
    }
    sq.iter().all(|v| v.is_nan() || v.is_finite()).then_some(sq)
}

/// One candidate: its lag, structure, and held-out cells' w·e².
struct Candidate {
    tau: f64,
    s: Structure,
    sq: Vec<f64>,
}

impl Candidate {
    fn params(&self) -> usize {
        self.s.order + 1 + self.s.regs.len() + usize::from(self.tau > 0.0)
    }
}

fn mean_sq(sq: &[f64], held: &[usize], total: f64) -> f64 {
    held.iter().map(|&i| sq[i]).sum::<f64>() / total
}

/// Whether `a`'s excess over `best` lies within `z` standard errors of it.
fn within_se(a: &[f64], best: &[f64], held: &[usize], total: f64, z: f64) -> bool {
    let d: Vec<f64> = held.iter().map(|&i| a[i] - best[i]).collect();
    let m = d.len() as f64;
    let mean = d.iter().sum::<f64>() / m;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1.0).max(1.0);
    mean * m / total <= z * (m * var).sqrt() / total
}

/// How far lag and hysteresis must beat the best polynomial of the logged
/// temperature, in standard errors of the held-out difference: a bias
/// wandering over minutes and a few cells of few samples give chance gains
/// of one standard error often enough, and the gain tested is the best of
/// some hundreds of candidates (lags × directions × orders), whose largest
/// chance gain passes two standard errors far more often than the one-sided
/// 2.3 % of a single test. Three (0.13 % for one test) holds the family's
/// chance near 5 % for a few dozen independent candidates; on pure cubics
/// two let a lag and hysteresis into one gyro of twelve seeds.
const ENTRY_SE: f64 = 3.0;

/// Per channel, the structure with lag and hysteresis where it beats the
/// polynomial of the logged temperature on held-out cells; `None` where the
/// plain polynomial is as good (the caller's own fit then stands).
pub(crate) fn search(runs: &[Run], f: &Frame) -> Vec<Option<Found>> {
    let nch = runs.first().map_or(0, |r| r.channels.len());
    let base = cells(runs, 0.0, f);
    if base.len() < 4 {
        return vec![None; nch];
    }
    let (nf, fold) = folds(&base, runs.len(), f);
    let held: Vec<usize> = (0..base.len()).filter(|&i| fold[i].is_some()).collect();
    if held.len() < 3 {
        return vec![None; nch];
    }
    let white: Vec<Vec<f64>> = (0..nch)
        .map(|k| {
            let v = white_per_run(runs, k);
            base.iter().map(|c| v[c.run] / c.n).collect()
        })
        .collect();
    let all_idx: Vec<usize> = (0..base.len()).collect();
    // Weights fixed per channel from the richest structure without lag, so
    // that every candidate is scored with the same ones.
    let rich = hysteretic(f.orders.1, NCOMBO / 2 + 1, AMP);
    let weights: Vec<Vec<f64>> = (0..nch)
        .map(|k| {
            let v = &white[k];
            if v.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
                return base.iter().map(|c| c.n).collect();
            }
            let params = rich.order + 1 + rich.regs.len();
            let tau2 = weights::floor_variance(v, params, |w| {
                let (c, _) = solve(&base, &all_idx, w, k, &rich)?;
                Some(base.iter().map(|b| b.x[k] - predict(b, &rich, &c)).collect())
            });
            let w: Vec<f64> = v.iter().map(|v| 1.0 / (v + tau2)).collect();
            let max = w.iter().copied().fold(0.0, f64::max);
            w.iter().map(|w| w / max).collect()
        })
        .collect();
    // A hysteresis is a difference between the directions: with one of
    // them a few stray samples, its term is the intercept over again.
    let heating: f64 = base.iter().filter(|c| c.heating).map(|c| c.n).sum();
    let all: f64 = base.iter().map(|c| c.n).sum();
    let both_ways = heating.min(all - heating) >= MIN_BRANCH_SHARE * all;
    let mut cands: Vec<Vec<Candidate>> = (0..nch).map(|_| Vec::new()).collect();
    // Staged, so the cost stays that of a few dozen structures per lag: the
    // direction's smoothing and rate scale chosen at the highest order with
    // the fullest amplitude, then every order plain and with that pair at
    // each amplitude.
    let score = |cs: &[Cell], tau: f64, cands: &mut Vec<Vec<Candidate>>| {
        for k in 0..nch {
            let push = |s: Structure, cands: &mut Vec<Vec<Candidate>>| {
                let sq = held_out(cs, &weights[k], k, &s, nf, &fold)?;
                let ms = mean_sq(&sq, &held, 1.0);
                cands[k].push(Candidate { tau, s, sq });
                Some(ms)
            };
            let mut best: Option<(usize, f64)> = None;
            for c in (0..NCOMBO).filter(|_| both_ways) {
                if let Some(ms) = push(hysteretic(f.orders.1, c, AMP), cands)
                    && best.is_none_or(|(_, b)| ms < b)
                {
                    best = Some((c, ms));
                }
            }
            for order in f.orders.0..=f.orders.1 {
                push(plain(order), cands);
                if let Some((c, _)) = best {
                    for amp in 1..=AMP {
                        if order < f.orders.1 || amp < AMP {
                            push(hysteretic(order, c, amp), cands);
                        }
                    }
                }
            }
        }
    };
    score(&base, 0.0, &mut cands);
    let mut grid_cells: Vec<(f64, Vec<Cell>)> = Vec::new();
    // A lag is told from a level only over several of its time constants,
    // and from a change of the polynomial only where the temperature moves
    // both ways: on runs that all heat (or all cool), T lagged by τ is T
    // shifted by the rate times τ, which a polynomial of T absorbs, and a
    // chance gain on held-out cells then projects into an equilibrium curve
    // shifted by degrees (a single 45 min PX4 heating took a 350 s lag).
    let longest = runs
        .iter()
        .map(|r| r.temp.len() as f64 / r.rate_hz)
        .fold(0.0, f64::max);
    for &tau in LAG_GRID_S
        .iter()
        .filter(|&&t| both_ways && t * MIN_RUN_LAGS <= longest)
    {
        let cs = cells(runs, tau, f);
        score(&cs, tau, &mut cands);
        grid_cells.push((tau, cs));
    }
    let total_w = |k: usize| held.iter().map(|&i| weights[k][i]).sum::<f64>();
    let mut out = Vec::with_capacity(nch);
    for k in 0..nch {
        let total = total_w(k);
        let list = &cands[k];
        let Some(best) = list
            .iter()
            .filter(|c| mean_sq(&c.sq, &held, total).is_finite())
            .min_by(|a, b| mean_sq(&a.sq, &held, total).total_cmp(&mean_sq(&b.sq, &held, total)))
        else {
            out.push(None);
            continue;
        };
        let mut order: Vec<&Candidate> = list.iter().collect();
        order.sort_by(|a, b| {
            a.params()
                .cmp(&b.params())
                .then(mean_sq(&a.sq, &held, total).total_cmp(&mean_sq(&b.sq, &held, total)))
        });
        let plain_best = list
            .iter()
            .filter(|c| c.tau == 0.0 && c.s.regs.is_empty())
            .min_by(|a, b| mean_sq(&a.sq, &held, total).total_cmp(&mean_sq(&b.sq, &held, total)));
        if plain_best.is_none_or(|p| within_se(&p.sq, &best.sq, &held, total, ENTRY_SE)) {
            out.push(None);
            continue;
        }
        let Some(chosen) = order
            .into_iter()
            .find(|c| within_se(&c.sq, &best.sq, &held, total, 1.0))
        else {
            out.push(None);
            continue;
        };
        if chosen.tau == 0.0 && chosen.s.regs.is_empty() {
            out.push(None);
            continue;
        }
        let s = chosen.s.clone();
        // The lag refined between its grid neighbours (a parabola in log τ
        // through the held-out scores), and bounded by the fit's own
        // profile (the weighted residual sum's rise of χ²(1)'s 95th
        // percentile, scaled by its value per degree of freedom).
        let (tau, lag_interval_s) = if chosen.tau > 0.0 {
            let scores: Vec<(f64, f64)> = list
                .iter()
                .filter(|c| c.tau > 0.0 && c.s == s)
                .map(|c| (c.tau, mean_sq(&c.sq, &held, total)))
                .collect();
            refine(runs, f, &grid_cells, &scores, &weights[k], k, &s, chosen.tau)
        } else {
            (0.0, None)
        };
        let cs = if tau > 0.0 {
            cells(runs, tau, f)
        } else {
            base.clone()
        };
        let Some(found) = finish(
            &cs,
            &weights[k],
            k,
            &s,
            tau,
            lag_interval_s,
            list,
            chosen.tau,
            &held,
            total,
        ) else {
            out.push(None);
            continue;
        };
        out.push(Some(found));
    }
    out
}

/// The weighted residual sum of squares of the structure fitted to all
/// cells, and its degrees of freedom.
fn rss(cs: &[Cell], w: &[f64], k: usize, s: &Structure) -> Option<(f64, f64)> {
    let idx: Vec<usize> = (0..cs.len()).collect();
    let (coef, _) = solve(cs, &idx, w, k, s)?;
    let q = cs
        .iter()
        .zip(w)
        .map(|(c, w)| w * (c.x[k] - predict(c, s, &coef)).powi(2))
        .sum();
    let dof = cs.len() as f64 - (s.order + 2 + s.regs.len()) as f64;
    Some((q, dof.max(1.0)))
}

/// The lag at the vertex of the parabola (in log τ) through the held-out
/// scores at the best grid point and its neighbours, and its 95 % interval
/// where the parabola through the fit's own residual sums there rises by
/// χ²(1)'s 95th percentile times the sum per degree of freedom.
#[allow(clippy::too_many_arguments)]
fn refine(
    runs: &[Run],
    f: &Frame,
    grid: &[(f64, Vec<Cell>)],
    held_out: &[(f64, f64)],
    w: &[f64],
    k: usize,
    s: &Structure,
    at: f64,
) -> (f64, Option<[f64; 2]>) {
    let Some(i) = grid.iter().position(|(t, _)| *t == at) else {
        return (at, None);
    };
    if i == 0 || i + 1 >= grid.len() {
        return (at, None);
    }
    let score = |t: f64| held_out.iter().find(|(x, _)| *x == t).map(|p| p.1);
    let (Some(h0), Some(h1), Some(h2)) = (score(grid[i - 1].0), score(at), score(grid[i + 1].0)) else {
        return (at, None);
    };
    let xs = [grid[i - 1].0.ln(), at.ln(), grid[i + 1].0.ln()];
    let Some((_, v)) = parabola(xs, [h0, h1, h2]) else {
        return (at, None);
    };
    let tau = v.clamp(xs[0], xs[2]).exp();
    let rs: Vec<Option<(f64, f64)>> = (i - 1..=i + 1).map(|j| rss(&grid[j].1, w, k, s)).collect();
    let (Some(r0), Some(r1), Some(r2)) = (rs[0], rs[1], rs[2]) else {
        return (tau, None);
    };
    let Some((curv, _)) = parabola(xs, [r0.0, r1.0, r2.0]) else {
        return (tau, None);
    };
    let (q, dof) = cells_rss(runs, f, tau, w, k, s).unwrap_or(r1);
    let half = (CHI2_1_95 * q / dof / curv).sqrt();
    let v = tau.ln();
    (
        tau,
        half.is_finite().then(|| [(v - half).exp(), (v + half).exp()]),
    )
}

/// The curvature a and vertex v of y = a(x − v)² + c through three points,
/// where it opens upward.
fn parabola(x: [f64; 3], y: [f64; 3]) -> Option<(f64, f64)> {
    let [x0, x1, x2] = x;
    let [y0, y1, y2] = y;
    let denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
    (a > 0.0 && a.is_finite()).then(|| (a, -b / (2.0 * a)))
}

fn cells_rss(runs: &[Run], f: &Frame, tau: f64, w: &[f64], k: usize, s: &Structure) -> Option<(f64, f64)> {
    rss(&cells(runs, tau, f), w, k, s)
}

#[allow(clippy::too_many_arguments)]
fn finish(
    cs: &[Cell],
    w: &[f64],
    k: usize,
    s: &Structure,
    tau: f64,
    lag_interval_s: Option<[f64; 2]>,
    list: &[Candidate],
    grid_tau: f64,
    held: &[usize],
    total: f64,
) -> Option<Found> {
    let idx: Vec<usize> = (0..cs.len()).collect();
    let (coef, inv) = solve(cs, &idx, w, k, s)?;
    let o = s.order + 1;
    let resid: Vec<f64> = cs.iter().map(|c| c.x[k] - predict(c, s, &coef)).collect();
    let q: f64 = resid.iter().zip(w).map(|(r, w)| w * r * r).sum();
    let dof = (cs.len() as f64 - (o + s.regs.len() + usize::from(tau > 0.0)) as f64).max(1.0);
    let n: f64 = cs.iter().map(|c| c.n).sum();
    let residual_rms = (cs.iter().zip(&resid).map(|(c, r)| c.n * r * r).sum::<f64>() / n).sqrt();
    let residual_max = resid.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    let hysteresis = (!s.regs.is_empty()).then(|| {
        let (relax_s, scale) = combo(s.regs[0] / AMP);
        let a0 = coef[o];
        let sd = 2.0 * (inv[(o, o)] * q / dof).max(0.0).sqrt();
        HysteresisTerm {
            coefficients: coef[o..].to_vec(),
            rate_scale_c_per_s: scale,
            smoothing_s: RATE_SMOOTHING_S,
            relax_s: Some(relax_s),
            heating_minus_cooling: 2.0 * a0,
            interval_95: [2.0 * a0 - 1.96 * sd, 2.0 * a0 + 1.96 * sd],
        }
    });
    let cross_validation = (0..=list.iter().map(|c| c.s.order).max().unwrap_or(0))
        .filter_map(|order| {
            list.iter()
                .find(|c| c.tau == grid_tau && c.s.order == order && c.s.regs == s.regs)
                .map(|c| (order, mean_sq(&c.sq, held, total).sqrt()))
        })
        .collect();
    let branches = cs
        .iter()
        .zip(&resid)
        .map(|(c, &residual)| BranchResidual {
            bin: c.key,
            heating: c.heating,
            n: c.n as usize,
            t: c.t,
            residual,
        })
        .collect();
    Some(Found {
        lag_s: (tau > 0.0).then_some(tau),
        lag_interval_s,
        order: s.order,
        coefficients: coef[..o].to_vec(),
        hysteresis,
        residual_rms,
        residual_max,
        cross_validation,
        branches,
    })
}

/// A channel's white-noise variance per sample in each run: half the mean
/// square of consecutive usable samples' differences.
fn white_per_run(runs: &[Run], k: usize) -> Vec<f64> {
    runs.iter()
        .map(|run| {
            let d = run.channels[k].data;
            let (mut sum, mut count) = (0.0, 0usize);
            for i in 1..d.len() {
                if usable(run, i) && usable(run, i - 1) {
                    sum += (d[i] - d[i - 1]).powi(2);
                    count += 1;
                }
            }
            if count > 0 { 0.5 * sum / count as f64 } else { 0.0 }
        })
        .collect()
}

/// The climb, °C/min, a projection's loss is quoted for.
pub const CLIMB_C_PER_MIN: f64 = 2.0;

/// RMS over the runs' cells (run, logged-temperature bin, direction) of
/// the mean of what `model` leaves of channel `name`, the level removed.
fn cell_rms(runs: &[Run], model: &crate::tcal::Model, k: usize, width: f64) -> Option<f64> {
    use std::collections::BTreeMap;
    let name = &model.channels.get(k)?.name;
    let mut cells: BTreeMap<(usize, i64, bool), (f64, f64)> = BTreeMap::new();
    for (ri, run) in runs.iter().enumerate() {
        let c = run.channels.iter().find(|c| &c.name == name)?;
        let mut left = c.data.to_vec();
        model.apply(name, &mut left, run.temp, run.rate_hz).ok()?;
        let heating = branch::heating(run.temp, run.rate_hz);
        for (i, v) in left.iter().enumerate() {
            if v.is_finite() && run.temp[i].is_finite() {
                let e = cells
                    .entry((ri, (run.temp[i] / width).floor() as i64, heating[i]))
                    .or_insert((0.0, 0.0));
                e.0 += v;
                e.1 += 1.0;
            }
        }
    }
    let n: f64 = cells.values().map(|c| c.1).sum();
    let level = cells.values().map(|c| c.0).sum::<f64>() / n;
    let ss: f64 = cells.values().map(|(s, m)| m * (s / m - level).powi(2)).sum();
    (n > 0.0).then(|| (ss / n).sqrt())
}

/// The model a flight stack can apply: each channel's polynomial of the
/// element's temperature, taken as one of the logged temperature (the
/// equilibrium curve: lag removed, between the branches), with what that
/// loses in its `projection`.
pub(crate) fn project(runs: &[Run], full: &crate::tcal::Model) -> crate::tcal::Model {
    let mut out = full.clone();
    for (k, ch) in out.channels.iter_mut().enumerate() {
        let c = &full.channels[k];
        if c.lag_s.is_none() && c.hysteresis_term.is_none() {
            continue;
        }
        let mut plain = full.clone();
        plain.channels[k].lag_s = None;
        plain.channels[k].hysteresis_term = None;
        // A steady climb at the reference: the element lags by r·τ and
        // the hysteresis sits on its heating branch.
        let r = CLIMB_C_PER_MIN / 60.0;
        let t = full.t_ref_c;
        let te = (t - r * c.lag_s.unwrap_or(0.0)).clamp(full.t_min_c, full.t_max_c);
        let u = (te - full.centre_c) / full.scale_c;
        let h = c.hysteresis_term.as_ref().map_or(0.0, |h| h.at(u, r));
        let climb_left = c.bias(full, te) + h - c.bias(full, t);
        ch.projection = Some(crate::tcal::Projection {
            lag_s: c.lag_s,
            heating_minus_cooling: c.hysteresis_term.as_ref().map(|h| h.heating_minus_cooling),
            climb_c_per_min: CLIMB_C_PER_MIN,
            climb_left,
            full_residual_rms: cell_rms(runs, full, k, full.bin_width_c),
            projected_residual_rms: cell_rms(runs, &plain, k, full.bin_width_c),
        });
        ch.lag_s = None;
        ch.lag_interval_s = None;
        ch.hysteresis_term = None;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(relax_s: Option<f64>) -> HysteresisTerm {
        HysteresisTerm {
            coefficients: vec![1.0],
            rate_scale_c_per_s: 0.05 / 60.0,
            // The earlier form smoothed over what is now the memory.
            smoothing_s: if relax_s.is_some() { RATE_SMOOTHING_S } else { 80.0 },
            relax_s,
            heating_minus_cooling: 2.0,
            interval_95: [1.9, 2.1],
        }
    }

    /// A 1 °C/min climb for 30 min, then a plateau, at 1 Hz.
    fn climb_then_hold() -> Vec<f64> {
        (0..4000).map(|i| 20.0 + (i.min(1800) as f64) / 60.0).collect()
    }

    #[test]
    fn a_model_without_relaxation_saturates_its_smoothed_rate_as_before() {
        let t = climb_then_hold();
        let d = term(None).direction(&t, 1.0);
        let want: Vec<f64> = element::smoothed_rate(&t, 1.0, 80.0)
            .iter()
            .map(|r| (r / (0.05 / 60.0)).tanh())
            .collect();
        assert_eq!(d, want);
    }

    #[test]
    fn the_relaxed_direction_fades_over_its_memory_on_a_plateau() {
        let t = climb_then_hold();
        let d = term(Some(160.0)).direction(&t, 1.0);
        // Saturated on the climb, then, once the 30 s rate has settled
        // (a few of 30 s after the climb stops), e^-1 of it per 160 s.
        assert!((d[1700] - 1.0).abs() < 1e-3, "{}", d[1700]);
        let (a, b) = (d[2100], d[2260]);
        assert!((b / a - (-1.0f64).exp()).abs() < 0.02, "{a} → {b}");
        // Smoothed first and saturated after, the term stays at full
        // strength for a while after the climb stops.
        let old = term(None).direction(&t, 1.0);
        assert!(old[1950] > 0.99 && d[1950] < 0.9, "{} {}", old[1950], d[1950]);
    }
}
