//! The statistics imutherm computes and the kind of data they are computed on.

use std::fmt;
use std::str::FromStr;

use crate::AllanError;

/// One Allan-family statistic. Names follow NIST SP 1065 and AllanTools.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stat {
    /// Non-overlapped Allan deviation (SP 1065 eq. 6/7).
    Adev,
    /// Overlapped Allan deviation (SP 1065 eq. 9/11).
    Oadev,
    /// Modified Allan deviation (SP 1065 eq. 14/15).
    Mdev,
    /// Time deviation, τ·MDEV/√3 (SP 1065 eq. 16).
    Tdev,
    /// Non-overlapped Hadamard deviation (SP 1065 eq. 17/18).
    Hdev,
    /// Overlapped Hadamard deviation (SP 1065 eq. 19/20).
    Ohdev,
    /// Total deviation on the doubly reflected series (SP 1065 eq. 25).
    Totdev,
    /// Modified total deviation (SP 1065 eq. 27), without the 0.73 bias correction.
    Mtotdev,
    /// Time total deviation, τ·MTOTDEV/√3 (SP 1065 eq. 28), without bias correction.
    Ttotdev,
    /// Hadamard total deviation (SP 1065 eq. 29), without the 0.995 bias correction.
    Htotdev,
    /// Theo1 deviation (SP 1065 eq. 30), without bias correction.
    Theo1,
}

impl Stat {
    /// Every statistic, in the order they are documented.
    pub const ALL: [Stat; 11] = [
        Stat::Adev,
        Stat::Oadev,
        Stat::Mdev,
        Stat::Tdev,
        Stat::Hdev,
        Stat::Ohdev,
        Stat::Totdev,
        Stat::Mtotdev,
        Stat::Ttotdev,
        Stat::Htotdev,
        Stat::Theo1,
    ];

    /// The lower-case name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Stat::Adev => "adev",
            Stat::Oadev => "oadev",
            Stat::Mdev => "mdev",
            Stat::Tdev => "tdev",
            Stat::Hdev => "hdev",
            Stat::Ohdev => "ohdev",
            Stat::Totdev => "totdev",
            Stat::Mtotdev => "mtotdev",
            Stat::Ttotdev => "ttotdev",
            Stat::Htotdev => "htotdev",
            Stat::Theo1 => "theo1",
        }
    }

    /// Stable32's stop ratio: the largest averaging factor is `N_phase / ratio`.
    ///
    /// Beyond it the estimates rest on too few terms to mean anything
    /// (Riley, "Evolution of frequency stability analysis software", Table III).
    pub fn stop_ratio(self) -> usize {
        match self {
            Stat::Adev | Stat::Hdev => 5,
            Stat::Oadev | Stat::Mdev | Stat::Tdev | Stat::Ohdev => 4,
            Stat::Totdev | Stat::Mtotdev | Stat::Ttotdev => 2,
            Stat::Htotdev => 3,
            Stat::Theo1 => 1,
        }
    }

    /// Whether the result is a time deviation (seconds of phase) rather than a
    /// frequency/rate deviation.
    pub fn is_time_deviation(self) -> bool {
        matches!(self, Stat::Tdev | Stat::Ttotdev)
    }

    /// Whether gap (NaN) samples can be skipped for this statistic.
    pub fn supports_gaps(self) -> bool {
        matches!(
            self,
            Stat::Adev | Stat::Oadev | Stat::Mdev | Stat::Tdev | Stat::Hdev | Stat::Ohdev
        )
    }
}

impl FromStr for Stat {
    type Err = AllanError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let lower = s.trim().to_ascii_lowercase();
        Stat::ALL
            .iter()
            .copied()
            .find(|st| st.name() == lower)
            .ok_or_else(|| AllanError::UnknownStat(s.to_string()))
    }
}

/// What the samples are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum DataType {
    /// Rate samples: fractional frequency in clock words; an IMU's angular
    /// rate or specific force. imutherm's default.
    #[default]
    Freq,
    /// Phase (time error) or integrated samples: the integral of the rate.
    Phase,
}

impl DataType {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            DataType::Freq => "freq",
            DataType::Phase => "phase",
        }
    }
}

impl FromStr for DataType {
    type Err = AllanError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "freq" | "frequency" | "rate" => Ok(DataType::Freq),
            "phase" | "integrated" => Ok(DataType::Phase),
            _ => Err(AllanError::UnknownDataType(s.to_string())),
        }
    }
}

/// Both are written as the name used on the command line and in JSON.
macro_rules! display_by_name {
    ($($t:ty),*) => {$(
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    )*};
}

display_by_name!(Stat, DataType);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for st in Stat::ALL {
            assert_eq!(st.name().parse::<Stat>().unwrap(), st);
        }
        assert!("bogus".parse::<Stat>().is_err());
        assert_eq!("PHASE".parse::<DataType>().unwrap(), DataType::Phase);
    }
}
