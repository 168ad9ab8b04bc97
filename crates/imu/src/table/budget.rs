//! How much memory the columns of one table may take.
//!
//! The columns are the only part of a read that grows with the file (a
//! line, a block and a batch are bounded), so they alone are counted, by
//! what they reserve, not what they fill. They may take half of the
//! machine's memory (the other half is for the analysis that follows,
//! which copies a channel or two), and a quarter of the process's
//! address-space limit (`ulimit -v`), which also counts thread stacks and
//! the allocator's reserved arenas. A gzip file of long rows, kilobytes
//! that unpack to gigabytes, is refused at the line that crosses the
//! limit, not by the allocator's abort; and the growth itself is fallible,
//! so a refusal by the system short of the limit is an error too.

use crate::error::ReadErrorKind;

/// The bytes the columns may take, or `None` when nothing bounds them.
pub(super) fn column_limit() -> Option<u64> {
    let memory = physical_memory().map(|m| m / 2);
    let address_space = address_space_limit().map(|a| a / 4);
    [memory, address_space].into_iter().flatten().min()
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
    (ok && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur)
}

const VALUE_BYTES: u64 = size_of::<f64>() as u64;

/// The bytes the columns reserve, against their limit.
#[derive(Debug, Clone, Copy)]
pub(super) struct Budget {
    held: u64,
    limit: Option<u64>,
}

impl Budget {
    /// A budget of `limit` bytes (`None`: unbounded).
    pub fn new(limit: Option<u64>) -> Self {
        Budget { held: 0, limit }
    }

    /// Takes `bytes` more, or says why they do not fit.
    fn take(&mut self, bytes: u64) -> Result<(), ReadErrorKind> {
        let held = self.held.saturating_add(bytes);
        match self.limit {
            Some(limit) if held > limit => Err(ReadErrorKind::TooLarge {
                held_mib: held.div_ceil(1 << 20),
                limit_mib: limit >> 20,
            }),
            _ => {
                self.held = held;
                Ok(())
            }
        }
    }

    /// Takes a column built elsewhere (a block's first rows), whole.
    pub fn adopt(&mut self, capacity: usize) -> Result<(), ReadErrorKind> {
        self.take((capacity as u64).saturating_mul(VALUE_BYTES))
    }

    /// Whether `bytes` more would fit.
    pub fn fits(&self, bytes: u64) -> bool {
        self.limit.is_none_or(|l| self.held.saturating_add(bytes) <= l)
    }

    /// Grows `column` to hold `extra` more values: to twice its capacity
    /// (amortised appends, as `Vec` grows), or by a quarter, or to just
    /// what they need, the first that fits the budget; counted before it
    /// is asked of the system, and asked fallibly. Stepping down keeps a
    /// column that fits from being refused for its doubling.
    pub fn grow(&mut self, column: &mut Vec<f64>, extra: usize) -> Result<(), ReadErrorKind> {
        let need = column.len().saturating_add(extra);
        let cap = column.capacity();
        if need <= cap {
            return Ok(());
        }
        let target = [cap.saturating_mul(2), cap.saturating_add(cap / 4)]
            .into_iter()
            .map(|t| t.max(need))
            .find(|&t| self.fits(((t - cap) as u64).saturating_mul(VALUE_BYTES)))
            .unwrap_or(need);
        self.reserve_exact(column, target)
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
        let mut b = Budget::new(Some(8 * 100));
        let mut c = Vec::new();
        b.grow(&mut c, 30).unwrap();
        c.extend([1.0; 30]);
        // Doubling while it fits: 60 reserved.
        b.grow(&mut c, 1).unwrap();
        assert_eq!((c.capacity(), b.held), (60, 8 * 60));
        c.extend([1.0; 30]);
        // 120 would not fit; a quarter more does.
        b.grow(&mut c, 1).unwrap();
        assert_eq!((c.capacity(), b.held), (75, 8 * 75));
        c.extend([1.0; 15]);
        // Then just what is needed, to the last value that fits.
        b.grow(&mut c, 25).unwrap();
        assert_eq!((c.capacity(), b.held), (100, 8 * 100));
        c.extend([1.0; 25]);
        let e = b.grow(&mut c, 1).unwrap_err();
        assert!(matches!(e, ReadErrorKind::TooLarge { .. }), "{e}");
        assert_eq!(c.capacity(), 100, "a refused growth asks nothing of the system");
        assert!(Budget::new(None).take(u64::MAX).is_ok());
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
        let mut c = vec![0.0; 4];
        let e = Budget::new(None).grow(&mut c, usize::MAX / 16).unwrap_err();
        assert!(matches!(e, ReadErrorKind::OutOfMemory { .. }), "{e}");
        assert_eq!(c.len(), 4);
    }
}
