//! What `--channels` names, parsed in one place for text logs and robot
//! logs alike: a group of channels (`gyro`, `accel`, `inertial`, `all`) or
//! one channel by its name or header.

use imu::Quantity;

/// A group of channels, by what they measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelGroup {
    /// The gyro axes (`gyro`, `gyros`).
    Gyro,
    /// The accelerometer axes (`accel`, `accels`, `acc`).
    Accel,
    /// Both (`inertial`, `imu`).
    Inertial,
    /// Every channel but the time column (`all`).
    All,
}

impl ChannelGroup {
    /// Whether a channel measuring `quantity` is in the group; `inertial`
    /// says whether it is an inertial axis, as its reader tells.
    pub fn holds(self, quantity: Quantity, inertial: bool) -> bool {
        match self {
            ChannelGroup::Gyro => inertial && quantity == Quantity::AngularRate,
            ChannelGroup::Accel => inertial && quantity == Quantity::Acceleration,
            ChannelGroup::Inertial => inertial,
            ChannelGroup::All => quantity != Quantity::Time,
        }
    }
}

/// One item of a channel list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ChannelSpec {
    /// A group, named in any case.
    Group(ChannelGroup),
    /// One channel: imutherm's name (`gyro_x`, any case) or the file's
    /// header or field, as written.
    Named(String),
}

impl ChannelSpec {
    /// Parses one item; spaces around it are not part of it.
    pub fn parse(text: &str) -> ChannelSpec {
        let text = text.trim();
        match text.to_ascii_lowercase().as_str() {
            "gyro" | "gyros" => ChannelSpec::Group(ChannelGroup::Gyro),
            "accel" | "accels" | "acc" => ChannelSpec::Group(ChannelGroup::Accel),
            "inertial" | "imu" => ChannelSpec::Group(ChannelGroup::Inertial),
            "all" => ChannelSpec::Group(ChannelGroup::All),
            _ => ChannelSpec::Named(text.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_in_any_case_and_names_as_written() {
        assert_eq!(
            ChannelSpec::parse(" Gyros "),
            ChannelSpec::Group(ChannelGroup::Gyro)
        );
        assert_eq!(ChannelSpec::parse("ACC"), ChannelSpec::Group(ChannelGroup::Accel));
        assert_eq!(
            ChannelSpec::parse("imu"),
            ChannelSpec::Group(ChannelGroup::Inertial)
        );
        assert_eq!(ChannelSpec::parse("all"), ChannelSpec::Group(ChannelGroup::All));
        assert_eq!(
            ChannelSpec::parse(" mpu_gyro_1[deg/s] "),
            ChannelSpec::Named("mpu_gyro_1[deg/s]".into())
        );
        assert_eq!(ChannelSpec::Group(ChannelGroup::Gyro), ChannelSpec::parse("gyro"));
    }

    #[test]
    fn a_group_holds_its_axes_and_all_holds_all_but_time() {
        use Quantity::*;
        assert!(ChannelGroup::Gyro.holds(AngularRate, true));
        assert!(
            !ChannelGroup::Gyro.holds(AngularRate, false) && !ChannelGroup::Gyro.holds(Acceleration, true)
        );
        assert!(
            ChannelGroup::Accel.holds(Acceleration, true) && !ChannelGroup::Accel.holds(Temperature, true)
        );
        assert!(
            ChannelGroup::Inertial.holds(Acceleration, true)
                && !ChannelGroup::Inertial.holds(Temperature, false)
        );
        assert!(ChannelGroup::All.holds(Temperature, false) && !ChannelGroup::All.holds(Time, false));
    }
}
