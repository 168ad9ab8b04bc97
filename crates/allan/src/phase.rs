//! Phase series: the one representation every statistic is computed on.
//!
//! Rate samples y (an IMU's output) become phase by
//! `x = [0, cumsum(y − mean(y))·τ0]` (NIST SP 1065 §5.2; AllanTools
//! `frequency2phase`): N rate samples give N+1 phase points. Removing the mean
//! first keeps the cumulative sum small, which matters for precision when a
//! gyro bias is large against its noise.
//!
//! Gap samples (NaN) are kept track of instead of being dropped, because
//! dropping them would join data from both sides of a gap into terms that
//! never existed. How a gap invalidates terms depends on the input:
//! - rate input: a missing rate sample is a missing phase *increment*; a term
//!   whose phase span covers it is skipped;
//! - phase input: a missing phase point invalidates only the terms that use
//!   that point, as AllanTools' gap-resistant `gradev` does.

use rayon::prelude::*;

use crate::{AllanError, DataType};

/// Samples per chunk of the parallel scan.
const SCAN_CHUNK: usize = 1 << 16;

/// What one scan of the samples finds; chunks are joined in order.
#[derive(Debug, Clone, Copy)]
struct Scan {
    nan: usize,
    first_infinite: Option<usize>,
    first_valid: Option<usize>,
    last_valid: Option<usize>,
    sum: f64,
    count: usize,
}

impl Scan {
    fn empty() -> Scan {
        Scan {
            nan: 0,
            first_infinite: None,
            first_valid: None,
            last_valid: None,
            sum: 0.0,
            count: 0,
        }
    }

    fn of(offset: usize, chunk: &[f64]) -> Scan {
        let mut s = Scan::empty();
        for (i, &v) in chunk.iter().enumerate() {
            if v.is_nan() {
                s.nan += 1;
            } else if v.is_infinite() {
                s.first_infinite.get_or_insert(offset + i);
            } else {
                s.first_valid.get_or_insert(offset + i);
                s.last_valid = Some(offset + i);
                s.sum += v;
                s.count += 1;
            }
        }
        s
    }

    fn join(a: Scan, b: Scan) -> Scan {
        Scan {
            nan: a.nan + b.nan,
            first_infinite: a.first_infinite.or(b.first_infinite),
            first_valid: a.first_valid.or(b.first_valid),
            last_valid: b.last_valid.or(a.last_valid),
            sum: a.sum + b.sum,
            count: a.count + b.count,
        }
    }
}

/// Where the gaps are, as a prefix count so any span is checked in O(1).
#[derive(Debug, Clone)]
pub(crate) struct GapIndex {
    /// `prefix[i]` = number of bad markers among the first `i` markers.
    prefix: Vec<u32>,
    /// What a marker stands for.
    kind: DataType,
}

impl GapIndex {
    fn build(bad: impl Iterator<Item = bool>, len: usize, kind: DataType) -> Self {
        let mut prefix = Vec::with_capacity(len + 1);
        let mut count = 0u32;
        prefix.push(0);
        for b in bad {
            count += u32::from(b);
            prefix.push(count);
        }
        GapIndex { prefix, kind }
    }

    /// The first bad marker, if any.
    fn first_bad(&self) -> Option<usize> {
        self.prefix.iter().position(|&c| c > 0).map(|i| i - 1)
    }

    /// Whether the phase span `[a, c]` (inclusive phase indices) crosses a gap:
    /// for rate input, a missing increment in `[a, c)`; for phase input, a
    /// missing point anywhere in `[a, c]`.
    #[inline]
    pub(crate) fn span_has_gap(&self, a: usize, c: usize) -> bool {
        match self.kind {
            DataType::Freq => self.prefix[c] != self.prefix[a],
            DataType::Phase => self.prefix[c + 1] != self.prefix[a],
        }
    }

    /// Whether the data were rate samples (gaps are missing increments).
    pub(crate) fn is_rate(&self) -> bool {
        self.kind == DataType::Freq
    }
}

/// An empty vector with room for `len` samples and the one phase point
/// rate data gains in the conversion, to be filled and handed to
/// [`crate::analyze_vec`] or [`PhaseSeries::from_vec`]. Pushed onto a full
/// vector, that point would reallocate, and copy, the whole series. The
/// buffer asks for huge pages: fresh memory is faulted in a page at a time,
/// and after other work has returned its memory to the system (a Python
/// session calling AllanTools between calls, say) those faults are a
/// measurable part of an O(N/m) statistic's time.
pub fn buffer_for(len: usize) -> Vec<f64> {
    let mut buffer = Vec::with_capacity(len.saturating_add(1));
    hugepages::advise(&mut buffer);
    buffer
}

/// A copy of `data` in a [`buffer_for`] its length.
pub(crate) fn copy_with_room(data: &[f64]) -> Vec<f64> {
    let mut copy = buffer_for(data.len());
    copy.extend_from_slice(data);
    copy
}

/// Phase points at a fixed interval τ0, with the record of any gaps.
#[derive(Debug, Clone)]
pub struct PhaseSeries {
    x: Vec<f64>,
    tau0: f64,
    gaps: Option<GapIndex>,
    nan_samples: usize,
    trimmed: usize,
    /// NaN samples trimmed from the start: input index = series index + this.
    leading: usize,
}

impl PhaseSeries {
    /// Builds the phase series from samples of the given type at `rate_hz`.
    ///
    /// Leading and trailing NaN samples are trimmed (they are missing edges,
    /// not gaps; AllanTools trims them too) but still counted in
    /// [`PhaseSeries::nan_samples`]. Infinite samples are an error.
    pub fn new(data: &[f64], data_type: DataType, rate_hz: f64) -> Result<Self, AllanError> {
        Self::from_vec(copy_with_room(data), data_type, rate_hz)
    }

    /// [`PhaseSeries::new`], converting the samples in place: no second copy
    /// of a long recording is made. Rate data gain one point: a vector with
    /// no spare capacity is reallocated for it ([`buffer_for`] leaves room).
    pub fn from_vec(mut data: Vec<f64>, data_type: DataType, rate_hz: f64) -> Result<Self, AllanError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(AllanError::InvalidRate(rate_hz));
        }
        // One parallel scan for everything the conversion needs to know,
        // its chunks joined in order: a reduction tree shaped by work
        // stealing would change the mean's last bits from run to run.
        let scan = data
            .par_chunks(SCAN_CHUNK)
            .enumerate()
            .map(|(c, chunk)| Scan::of(c * SCAN_CHUNK, chunk))
            .collect::<Vec<_>>()
            .into_iter()
            .fold(Scan::empty(), Scan::join);
        if let Some(index) = scan.first_infinite {
            return Err(AllanError::Infinite { index });
        }
        let (nan_samples, sum, count) = (scan.nan, scan.sum, scan.count);
        let tau0 = 1.0 / rate_hz;
        let first = scan.first_valid.unwrap_or(data.len());
        let last = scan.last_valid.map_or(0, |l| l + 1).max(first);
        let total = data.len();
        data.truncate(last);
        if first > 0 {
            data.drain(..first);
        }
        let trimmed = total - data.len();
        let interior_gaps = nan_samples - trimmed;
        let gaps = (interior_gaps > 0)
            .then(|| GapIndex::build(data.iter().map(|v| v.is_nan()), data.len(), data_type));
        if data_type == DataType::Freq {
            let mean = if count > 0 { sum / count as f64 } else { 0.0 };
            // x[k] is the sum of the increments before sample k: each slot
            // is read as a rate and overwritten with the phase before it.
            // A missing increment adds nothing; the gap index marks every
            // span across it as unusable.
            //
            // A prefix sum in two parallel passes: chunk totals, then each
            // chunk's running sum from the total of those before it.
            let increment = |y: f64| if y.is_nan() { 0.0 } else { (y - mean) * tau0 };
            let totals: Vec<f64> = data
                .par_chunks(SCAN_CHUNK)
                .map(|c| c.iter().map(|&y| increment(y)).sum())
                .collect();
            let starts: Vec<f64> = totals
                .iter()
                .scan(0.0, |acc, t| {
                    let start = *acc;
                    *acc += t;
                    Some(start)
                })
                .collect();
            let ends: Vec<f64> = data
                .par_chunks_mut(SCAN_CHUNK)
                .zip(starts)
                .map(|(chunk, start)| {
                    let mut acc = start;
                    for v in chunk.iter_mut() {
                        let y = *v;
                        *v = acc;
                        acc += increment(y);
                    }
                    acc
                })
                .collect();
            data.push(ends.last().copied().unwrap_or(0.0));
        }
        Ok(PhaseSeries {
            x: data,
            tau0,
            gaps,
            nan_samples,
            trimmed,
            leading: first.min(total),
        })
    }

    /// The phase points (NaN where a phase input had a gap).
    pub fn points(&self) -> &[f64] {
        &self.x
    }

    /// The sampling interval τ0 in seconds.
    pub fn tau0(&self) -> f64 {
        self.tau0
    }

    /// Number of phase points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are no phase points at all.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Number of NaN samples in the input, edges included.
    pub fn nan_samples(&self) -> usize {
        self.nan_samples
    }

    /// Number of NaN samples trimmed from the two ends.
    pub fn trimmed_samples(&self) -> usize {
        self.trimmed
    }

    /// Index in the input samples of the first NaN inside the series (not
    /// an edge), if any. For rate input it cannot be read off the phase
    /// points, where a missing increment leaves no NaN.
    pub fn first_gap(&self) -> Option<usize> {
        self.gaps.as_ref()?.first_bad().map(|i| i + self.leading)
    }

    /// Whether there are gaps inside the series.
    pub fn has_gaps(&self) -> bool {
        self.gaps.is_some()
    }

    pub(crate) fn gap_index(&self) -> Option<&GapIndex> {
        self.gaps.as_ref()
    }

    /// The longest stretch of phase points that no gap crosses: the data used
    /// for noise identification when the series has gaps.
    pub(crate) fn longest_clean_stretch(&self) -> &[f64] {
        let Some(g) = &self.gaps else {
            return &self.x;
        };
        let n = self.x.len();
        let mut best = (0, 0);
        let mut start = 0;
        for i in 1..=n {
            let cut = i == n
                || if g.is_rate() {
                    g.span_has_gap(i - 1, i)
                } else {
                    self.x[i].is_nan()
                };
            if cut {
                if i - start.min(i) > best.1 - best.0 {
                    best = (start.min(i), i);
                }
                // A missing phase point is itself excluded; a missing
                // increment only separates its two neighbours.
                start = if g.is_rate() { i } else { i + 1 };
            }
        }
        &self.x[best.0..best.1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_to_phase_matches_sp1065_table_30() {
        // NIST SP 1065 Table 30 input and the phase AllanTools' test quotes.
        let y = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];
        let p = PhaseSeries::new(&y, DataType::Freq, 1.0).unwrap();
        let expect = [
            0.0, 103.11111, 123.22222, 157.33333, 166.44444, 48.55555, -96.33333, -2.22222, 111.88889, 0.0,
        ];
        assert_eq!(p.len(), 10);
        for (a, b) in p.points().iter().zip(expect) {
            assert!((a - b).abs() < 1e-4, "{a} vs {b}");
        }
    }

    #[test]
    fn edges_are_trimmed_and_gaps_indexed() {
        let y = [f64::NAN, 1.0, 2.0, f64::NAN, 3.0, 4.0, f64::NAN];
        let p = PhaseSeries::new(&y, DataType::Freq, 2.0).unwrap();
        assert_eq!(p.nan_samples(), 3);
        assert_eq!(p.trimmed_samples(), 2);
        assert_eq!(p.len(), 6);
        assert!(p.has_gaps());
        let g = p.gap_index().unwrap();
        assert!(!g.span_has_gap(0, 2));
        assert!(g.span_has_gap(0, 3));
        assert!(g.span_has_gap(2, 3));
        assert!(!g.span_has_gap(3, 5));
        assert_eq!(p.longest_clean_stretch().len(), 3);
        // The input's index, leading NaN counted; a missing rate increment
        // leaves no NaN among the phase points to find it by.
        assert_eq!(p.first_gap(), Some(3));
        assert!(p.points().iter().all(|v| !v.is_nan()));
        let phase = PhaseSeries::new(&y, DataType::Phase, 2.0).unwrap();
        assert_eq!(phase.first_gap(), Some(3));
        let clean = PhaseSeries::new(&[f64::NAN, 1.0, 2.0], DataType::Freq, 2.0).unwrap();
        assert_eq!(clean.first_gap(), None);
    }

    #[test]
    fn rejects_bad_rate_and_infinity() {
        assert!(PhaseSeries::new(&[1.0], DataType::Freq, 0.0).is_err());
        assert!(PhaseSeries::new(&[1.0, f64::INFINITY], DataType::Freq, 1.0).is_err());
        let all_nan = PhaseSeries::new(&[f64::NAN; 4], DataType::Freq, 1.0).unwrap();
        assert_eq!(all_nan.len(), 1);
    }
}
