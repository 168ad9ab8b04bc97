//! How much memory the columns of one table may take.
//!
//! The columns are the only part of a read that grows with the file (a
//! line, a block and a batch are bounded), so they alone are counted, by
//! what they reserve, not what they fill. Their bound is the input's, not
//! the machine's: a value takes at least two bytes of text (`0,`) and eight
//! as a double, so the rows of a text hold at most four bytes of columns a
//! byte, eight with the growth by doubling ([`BYTES_PER_BYTE_READ`]). A
//! regular file's size is known before the body: its columns may take that
//! multiple of it. A compressed or piped input's size is not, so the limit
//! grows with the bytes it has given so far, up to [`STREAM_CAP`], the same
//! on every machine: a gzip file of long rows, kilobytes that unpack to
//! gigabytes, is refused at the line that crosses the cap, under a gigabyte
//! resident, while ten million rows of seven columns (534 MiB) still read.
//! Gaps (short bad lines made rows of NaN) are what the multiple does
//! bound in a stream; [`FLOOR`] keeps a small file's gaps from being
//! refused. Below those, half of the machine's memory (the other half is
//! for the analysis that follows, which copies a channel or two), and a
//! quarter of the process's address-space limit (`ulimit -v`), which also
//! counts thread stacks and the allocator's reserved arenas. The growth
//! itself is fallible, so a refusal by the system short of the limit is an
//! error too.

use std::sync::Arc;

use super::input::Seen;

use crate::error::{LimitBound, ReadErrorKind};

/// Bytes of columns a byte of text may give (see the module's notes).
pub const BYTES_PER_BYTE_READ: u64 = 8;

/// What the columns may always take, whatever the input's size: a small
/// file's gaps.
pub const FLOOR: u64 = 64 << 20;

/// The most the columns of an input of unknown size (gzip, a pipe) may
/// take, on any machine.
pub const STREAM_CAP: u64 = 640 << 20;

// Ten million rows of seven columns fit the cap.
const _: () = assert!(10_000_000 * 7 * VALUE_BYTES <= STREAM_CAP);

/// The bytes the columns may take, or `None` when nothing bounds them:
/// the machine's and the process's bounds.
pub fn column_limit() -> Option<u64> {
    machine_limit().map(|(l, _)| l)
}

fn machine_limit() -> Option<(u64, LimitBound)> {
    let memory = physical_memory().map(|m| m / 2);
    let address_space = address_space_limit().map(|a| a / 4);
    [memory, address_space]
        .into_iter()
        .flatten()
        .min()
        .map(|l| (l, LimitBound::Machine))
}

/// The limit of one read: a ceiling, and for a stream the bytes it has
/// given so far.
#[derive(Debug, Clone, Default)]
pub(super) struct Limit {
    ceiling: Option<(u64, LimitBound)>,
    read: Option<Arc<Seen>>,
}

impl Limit {
    /// A fixed limit of `bytes` (`None`: unbounded).
    #[cfg(test)]
    pub fn fixed(bytes: Option<u64>) -> Self {
        Limit {
            ceiling: bytes.map(|b| (b, LimitBound::Machine)),
            read: None,
        }
    }

    /// The limit of an input: a regular file of `file_bytes`, or a stream
    /// whose decoded bytes so far `read` counts.
    pub fn of_input(file_bytes: Option<u64>, read: &Arc<Seen>) -> Self {
        Self::of_input_capped(file_bytes, read, STREAM_CAP)
    }

    /// [`Limit::of_input`] with a stream's cap of `cap` bytes.
    pub fn of_input_capped(file_bytes: Option<u64>, read: &Arc<Seen>, cap: u64) -> Self {
        let input = match file_bytes {
            Some(b) if b.saturating_mul(BYTES_PER_BYTE_READ) <= FLOOR => (FLOOR, LimitBound::Floor),
            Some(b) => (
                b.saturating_mul(BYTES_PER_BYTE_READ),
                LimitBound::FileSize { bytes: b },
            ),
            None => (cap, LimitBound::StreamCap),
        };
        let ceiling = [Some(input), machine_limit()]
            .into_iter()
            .flatten()
            .min_by_key(|l| l.0);
        Limit {
            ceiling,
            read: file_bytes.is_none().then(|| Arc::clone(read)),
        }
    }

    /// The most the limit can become, and what sets it.
    pub fn ceiling(&self) -> Option<(u64, LimitBound)> {
        self.ceiling
    }

    /// The limit now, and what sets it.
    fn now(&self) -> Option<(u64, LimitBound)> {
        let ceiling = self.ceiling?;
        let Some(read) = &self.read else {
            return Some(ceiling);
        };
        let bytes = read.bytes();
        let grown = bytes.saturating_mul(BYTES_PER_BYTE_READ);
        Some(if grown >= ceiling.0 {
            ceiling
        } else if grown > FLOOR {
            (grown, LimitBound::BytesRead { bytes })
        } else if FLOOR < ceiling.0 {
            (FLOOR, LimitBound::Floor)
        } else {
            ceiling
        })
    }
}

/// The machine's memory, from `sysconf`.
fn physical_memory() -> Option<u64> {
    // SAFETY: sysconf reads a system constant; no memory is passed.
    let (pages, size) = unsafe {
        (
            libc::sysconf(libc::_SC_PHYS_PAGES),
            libc::sysconf(libc::_SC_PAGESIZE),
        )
    };
    (pages > 0 && size > 0).then(|| pages as u64 * size as u64)
}

/// The process's address-space limit, when one is set.
fn address_space_limit() -> Option<u64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the struct it is given, which lives here.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0;
    // `rlim_t` is 32 bits wide on 32-bit Linux (the Pi's armv7) and 64 on
    // 64-bit, so the widening is needed on one and a no-op on the other.
    #[allow(clippy::useless_conversion)]
    let current = u64::from(limit.rlim_cur);
    (ok && limit.rlim_cur != libc::RLIM_INFINITY).then_some(current)
}

const VALUE_BYTES: u64 = size_of::<f64>() as u64;

/// The bytes the columns reserve, against their limit.
#[derive(Debug, Clone)]
pub(super) struct Budget {
    held: u64,
    limit: Limit,
}

impl Budget {
    /// A budget of `limit` bytes (`None`: unbounded).
    #[cfg(test)]
    pub fn new(limit: Option<u64>) -> Self {
        Self::within(Limit::fixed(limit))
    }

    /// A budget held to `limit`.
    pub fn within(limit: Limit) -> Self {
        Budget { held: 0, limit }
    }

    /// Takes `bytes` more, or says why they do not fit.
    fn take(&mut self, bytes: u64) -> Result<(), ReadErrorKind> {
        let held = self.held.saturating_add(bytes);
        match self.limit.now() {
            Some((limit, bound)) if held > limit => Err(ReadErrorKind::TooLarge {
                held_mib: held.div_ceil(1 << 20),
                limit_mib: limit >> 20,
                bound,
            }),
            _ => {
                self.held = held;
                Ok(())
            }
        }
    }

    /// Takes a column built elsewhere (a block's first rows), whole, in
    /// place of an empty one of capacity `old` (a block of comments only
    /// leaves one), which is given back.
    pub fn adopt(&mut self, old: usize, capacity: usize) -> Result<(), ReadErrorKind> {
        self.held = self.held.saturating_sub((old as u64).saturating_mul(VALUE_BYTES));
        self.take((capacity as u64).saturating_mul(VALUE_BYTES))
    }

    /// Whether `bytes` more would fit.
    pub fn fits(&self, bytes: u64) -> bool {
        self.limit
            .now()
            .is_none_or(|(l, _)| self.held.saturating_add(bytes) <= l)
    }

    /// Grows each column to hold its `extra` more values: to twice its
    /// capacity (amortised appends, as `Vec` grows), or by a quarter, or by
    /// an even share of what is left, the first step that fits the budget
    /// for all the columns together; counted before it is asked of the
    /// system, and asked fallibly. Stepping down keeps columns that fit
    /// from being refused for their doubling; the last step takes all that
    /// is left at once, so the columns are not copied block after block.
    pub fn grow(&mut self, columns: &mut [Vec<f64>], extra: &[usize]) -> Result<(), ReadErrorKind> {
        let growing = columns
            .iter()
            .zip(extra)
            .filter(|(c, e)| c.len() + *e > c.capacity())
            .count();
        let left = self.limit.now().map_or(0, |(l, _)| l.saturating_sub(self.held));
        let share = usize::try_from(left / VALUE_BYTES / growing.max(1) as u64).unwrap_or(usize::MAX);
        let target = |c: &Vec<f64>, extra: usize, step: usize| {
            let need = c.len().saturating_add(extra);
            let cap = c.capacity();
            match step {
                _ if need <= cap => cap,
                0 => cap.saturating_mul(2).max(need),
                1 => cap.saturating_add(cap / 4).max(need),
                _ => cap.saturating_add(share).max(need),
            }
        };
        let bytes = |step| {
            columns.iter().zip(extra).fold(0u64, |sum, (c, &e)| {
                let more = (target(c, e, step) - c.capacity()) as u64;
                sum.saturating_add(more.saturating_mul(VALUE_BYTES))
            })
        };
        let step = (0..2).find(|&s| self.fits(bytes(s))).unwrap_or(2);
        for (c, &e) in columns.iter_mut().zip(extra) {
            let t = target(c, e, step);
            self.reserve_exact(c, t)?;
        }
        Ok(())
    }

    /// Gives `column` a capacity of `capacity` values, counted and asked
    /// fallibly.
    pub fn reserve_exact(&mut self, column: &mut Vec<f64>, capacity: usize) -> Result<(), ReadErrorKind> {
        let more = capacity.saturating_sub(column.capacity());
        if more == 0 {
            return Ok(());
        }
        self.take((more as u64).saturating_mul(VALUE_BYTES))?;
        let before = column.capacity();
        column
            .try_reserve_exact(capacity - column.len())
            .map_err(|_| ReadErrorKind::OutOfMemory {
                needed_mib: (capacity as u64 * VALUE_BYTES) >> 20,
            })?;
        // The allocator may give more: what it gave is what is held.
        let given = column.capacity() - before;
        self.held = self
            .held
            .saturating_add(given.saturating_sub(more) as u64 * VALUE_BYTES);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_counts_capacity_and_refuses_the_growth_that_crosses_it() {
        // Two columns of 8 × 100 bytes each.
        let mut b = Budget::new(Some(2 * 8 * 100));
        let mut c = vec![Vec::new(), Vec::new()];
        let fill = |c: &mut [Vec<f64>], n| c.iter_mut().for_each(|c| c.extend(std::iter::repeat_n(1.0, n)));
        b.grow(&mut c, &[30, 30]).unwrap();
        fill(&mut c, 30);
        // Doubling while it fits: 60 reserved each.
        b.grow(&mut c, &[1, 1]).unwrap();
        assert_eq!((c[0].capacity(), c[1].capacity(), b.held), (60, 60, 2 * 8 * 60));
        fill(&mut c, 30);
        // 120 would not fit both; a quarter more does, for both alike.
        b.grow(&mut c, &[1, 1]).unwrap();
        assert_eq!((c[0].capacity(), c[1].capacity(), b.held), (75, 75, 2 * 8 * 75));
        fill(&mut c, 15);
        b.grow(&mut c, &[1, 1]).unwrap();
        assert_eq!(c[0].capacity(), 93);
        fill(&mut c, 18);
        // Then all that is left, at once.
        b.grow(&mut c, &[1, 1]).unwrap();
        assert_eq!((c[0].capacity(), b.held), (100, 2 * 8 * 100));
        fill(&mut c, 7);
        let e = b.grow(&mut c, &[1, 1]).unwrap_err();
        assert!(matches!(e, ReadErrorKind::TooLarge { .. }), "{e}");
        assert_eq!(
            c[0].capacity(),
            100,
            "a refused growth asks nothing of the system"
        );
        assert!(Budget::new(None).take(u64::MAX).is_ok());
    }

    #[test]
    fn a_streams_limit_grows_with_its_bytes_up_to_its_cap_and_a_files_is_its_size() {
        use std::sync::atomic::Ordering;
        let read = Arc::new(Seen::default());
        let cap = 640 << 20;
        let stream = Limit::of_input_capped(None, &read, cap);
        let machine = machine_limit().map_or(u64::MAX, |(l, _)| l);
        let expect = |l: u64, b| {
            if l <= machine {
                Some((l, b))
            } else {
                stream.ceiling()
            }
        };
        assert_eq!(stream.now(), expect(FLOOR, LimitBound::Floor));
        read.bytes.store(20 << 20, Ordering::Relaxed);
        assert_eq!(
            stream.now(),
            expect(160 << 20, LimitBound::BytesRead { bytes: 20 << 20 })
        );
        // A bomb's gigabytes of text: the cap, wherever it runs.
        read.bytes.store(4 << 30, Ordering::Relaxed);
        assert_eq!(stream.now(), expect(cap, LimitBound::StreamCap));
        // A regular file: its size, known before the body, whatever is read.
        read.bytes.store(0, Ordering::Relaxed);
        let file = Limit::of_input_capped(Some(1 << 30), &read, cap);
        assert_eq!(
            file.now(),
            expect(8 << 30, LimitBound::FileSize { bytes: 1 << 30 })
        );
        let small = Limit::of_input_capped(Some(1000), &read, cap);
        assert_eq!(small.now(), expect(FLOOR, LimitBound::Floor));
    }

    #[test]
    fn the_limit_is_within_the_memory_and_address_space_given() {
        let limit = column_limit();
        if let Some(a) = address_space_limit() {
            assert!(limit.is_some_and(|l| l <= a / 4));
        }
        if let Some(p) = physical_memory() {
            assert!(limit.is_some_and(|l| l <= p / 2 && l > 0));
        }
    }

    #[test]
    fn a_growth_the_system_refuses_is_an_error() {
        let mut c = vec![vec![0.0; 4]];
        let e = Budget::new(None).grow(&mut c, &[usize::MAX / 16]).unwrap_err();
        assert!(matches!(e, ReadErrorKind::OutOfMemory { .. }), "{e}");
        assert_eq!(c[0].len(), 4);
    }
}
