//! Temperature: the chamber's profile over time, and the sensor's own
//! temperature, which follows the chamber's with a first-order lag.

use std::path::PathBuf;

use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::SimError;

/// The chamber temperature over time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Profile {
    /// Constant, with a small random fluctuation (an Ornstein–Uhlenbeck
    /// process of standard deviation `fluctuation_c` and correlation time
    /// `fluctuation_tau_s`), as a regulated chamber holds it.
    Constant {
        /// The set point, °C.
        temp_c: f64,
        /// Standard deviation of the fluctuation, °C.
        #[serde(default)]
        fluctuation_c: f64,
        /// Correlation time of the fluctuation, s.
        #[serde(default = "default_fluctuation_tau")]
        fluctuation_tau_s: f64,
    },
    /// Newton cooling from `start_c` towards `ambient_c` with time constant
    /// `tau_s` (the thesis's 100 °C → 20 °C run).
    Cooling {
        /// Temperature at t = 0, °C.
        start_c: f64,
        /// Ambient temperature, °C.
        ambient_c: f64,
        /// Time constant, s.
        tau_s: f64,
    },
    /// A linear ramp from `from_c` to `to_c` over `duration_s`, then held.
    Ramp {
        /// Start, °C.
        from_c: f64,
        /// End, °C.
        to_c: f64,
        /// Ramp duration, s.
        duration_s: f64,
    },
    /// Set points held `hold_s` each, reached through a first-order heater
    /// response of time constant `heater_tau_s`.
    Steps {
        /// The set points in order, °C.
        levels_c: Vec<f64>,
        /// How long each is held, s.
        hold_s: f64,
        /// Heater response time constant, s.
        #[serde(default = "default_heater_tau")]
        heater_tau_s: f64,
    },
    /// Read from a file of `time_s, temp_c` rows (comma or space separated,
    /// `#` comments), linearly interpolated and held beyond its ends.
    File {
        /// The file.
        path: PathBuf,
    },
}

/// Absolute zero, °C.
const ABSOLUTE_ZERO_C: f64 = -273.15;
/// The highest temperature a profile may reach, °C: far above any IMU's
/// survival (MEMS parts are rated to 125 or 150 °C, solder melts near 220).
const MAX_TEMPERATURE_C: f64 = 1000.0;

fn default_fluctuation_tau() -> f64 {
    60.0
}

fn default_heater_tau() -> f64 {
    120.0
}

impl Profile {
    /// Held at `temp_c` with a fluctuation of standard deviation
    /// `fluctuation_c`, of the default correlation time.
    pub fn constant(temp_c: f64, fluctuation_c: f64) -> Profile {
        Profile::Constant {
            temp_c,
            fluctuation_c,
            fluctuation_tau_s: default_fluctuation_tau(),
        }
    }

    /// Parses the command line's short form: `constant:34[:0.05]`,
    /// `cooling:100:20:1800`, `ramp:20:80:3600`, `steps:30,45,60:1200`,
    /// `file:PATH`.
    pub fn parse(spec: &str) -> Result<Profile, SimError> {
        let bad = |why: &str| SimError::Profile(format!("'{spec}': {why}"));
        let (kind, rest) = spec
            .split_once(':')
            .ok_or_else(|| bad("expected KIND:PARAMETERS"))?;
        let nums = |s: &str| -> Result<Vec<f64>, SimError> {
            s.split(':')
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .map_err(|_| bad(&format!("'{v}' is not a number")))
                })
                .collect()
        };
        let p = match kind.trim() {
            "constant" => match nums(rest)?.as_slice() {
                [t] => Profile::Constant {
                    temp_c: *t,
                    fluctuation_c: 0.0,
                    fluctuation_tau_s: default_fluctuation_tau(),
                },
                [t, f] => Profile::Constant {
                    temp_c: *t,
                    fluctuation_c: *f,
                    fluctuation_tau_s: default_fluctuation_tau(),
                },
                _ => return Err(bad("constant:TEMP_C[:FLUCTUATION_C]")),
            },
            "cooling" => match nums(rest)?.as_slice() {
                [s, a, t] => Profile::Cooling {
                    start_c: *s,
                    ambient_c: *a,
                    tau_s: *t,
                },
                _ => return Err(bad("cooling:START_C:AMBIENT_C:TAU_S")),
            },
            "ramp" => match nums(rest)?.as_slice() {
                [f, t, d] => Profile::Ramp {
                    from_c: *f,
                    to_c: *t,
                    duration_s: *d,
                },
                _ => return Err(bad("ramp:FROM_C:TO_C:DURATION_S")),
            },
            "steps" => {
                let (levels, hold) = rest.rsplit_once(':').ok_or_else(|| bad("steps:T1,T2,…:HOLD_S"))?;
                let levels_c = levels
                    .split(',')
                    .map(|v| {
                        v.trim()
                            .parse::<f64>()
                            .map_err(|_| bad(&format!("'{v}' is not a number")))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                let hold_s = hold
                    .trim()
                    .parse::<f64>()
                    .map_err(|_| bad("the hold time is not a number"))?;
                Profile::Steps {
                    levels_c,
                    hold_s,
                    heater_tau_s: default_heater_tau(),
                }
            }
            "file" => Profile::File {
                path: PathBuf::from(rest),
            },
            other => {
                return Err(bad(&format!(
                    "unknown kind '{other}' (constant, cooling, ramp, steps, file)"
                )));
            }
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), SimError> {
        // A temperature is finite, above absolute zero, and below where
        // any IMU (or its solder) survives: beyond that it is a typo, and
        // a run at 1e308 °C would be written as if it were an experiment.
        let finite = |name: &str, v: f64| {
            if !v.is_finite() {
                Err(SimError::InvalidParameter {
                    name: format!("profile.{name}"),
                    value: v,
                    why: "must be a finite number",
                })
            } else if !(ABSOLUTE_ZERO_C..=MAX_TEMPERATURE_C).contains(&v) {
                Err(SimError::InvalidParameter {
                    name: format!("profile.{name}"),
                    value: v,
                    why: "is beyond physics: a temperature lies between absolute zero (-273.15 °C) and 1000 °C",
                })
            } else {
                Ok(())
            }
        };
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SimError::InvalidParameter {
                    name: format!("profile.{name}"),
                    value: v,
                    why: "must be a positive number of seconds",
                })
            }
        };
        match self {
            Profile::Constant {
                temp_c,
                fluctuation_c,
                fluctuation_tau_s,
            } => {
                finite("temp_c", *temp_c)?;
                if !(fluctuation_c.is_finite() && (0.0..=MAX_TEMPERATURE_C).contains(fluctuation_c)) {
                    return Err(SimError::InvalidParameter {
                        name: "profile.fluctuation_c".into(),
                        value: *fluctuation_c,
                        why: "must be ≥ 0",
                    });
                }
                positive("fluctuation_tau_s", *fluctuation_tau_s)
            }
            Profile::Cooling {
                start_c,
                ambient_c,
                tau_s,
            } => {
                finite("start_c", *start_c)?;
                finite("ambient_c", *ambient_c)?;
                positive("tau_s", *tau_s)
            }
            Profile::Ramp {
                from_c,
                to_c,
                duration_s,
            } => {
                finite("from_c", *from_c)?;
                finite("to_c", *to_c)?;
                positive("duration_s", *duration_s)
            }
            Profile::Steps {
                levels_c,
                hold_s,
                heater_tau_s,
            } => {
                if levels_c.is_empty() {
                    return Err(SimError::Profile("steps need at least one level".into()));
                }
                for v in levels_c {
                    finite("levels_c", *v)?;
                }
                positive("hold_s", *hold_s)?;
                positive("heater_tau_s", *heater_tau_s)
            }
            Profile::File { .. } => Ok(()),
        }
    }

    /// A short description for metadata.
    pub fn describe(&self) -> String {
        match self {
            Profile::Constant {
                temp_c,
                fluctuation_c,
                ..
            } => format!("constant {temp_c} °C ± {fluctuation_c} °C"),
            Profile::Cooling {
                start_c,
                ambient_c,
                tau_s,
            } => format!("cooling {start_c} °C → {ambient_c} °C, time constant {tau_s} s"),
            Profile::Ramp {
                from_c,
                to_c,
                duration_s,
            } => format!("ramp {from_c} °C → {to_c} °C in {duration_s} s"),
            Profile::Steps { levels_c, hold_s, .. } => format!("steps {levels_c:?} °C, {hold_s} s each"),
            Profile::File { path } => format!("from {}", path.display()),
        }
    }
}

/// A profile ready to be stepped through in time.
#[derive(Debug, Clone)]
pub struct Thermal {
    profile: Profile,
    table: Vec<(f64, f64)>,
    /// Where the last lookup in `table` was: time only moves forward.
    cursor: usize,
    tau0: f64,
    /// Chamber state where it has one (heater response, fluctuation).
    state: f64,
    fluctuation: f64,
    /// Per-sample decay and kick of the fluctuation, or of the heater.
    decay: f64,
    kick: f64,
    chamber: f64,
    /// The sensor's own temperature.
    sensor: f64,
    lag_decay: f64,
    step: u64,
}

impl Thermal {
    /// Prepares `profile` at sample interval `tau0`, with the sensor lagging
    /// the chamber by a first-order time constant `lag_s` (0: no lag).
    pub fn new(profile: &Profile, tau0: f64, lag_s: f64) -> Result<Thermal, SimError> {
        profile.validate()?;
        let table = match profile {
            Profile::File { path } => read_table(path)?,
            _ => Vec::new(),
        };
        let (decay, kick) = match profile {
            Profile::Constant {
                fluctuation_c,
                fluctuation_tau_s,
                ..
            } => {
                let phi = (-tau0 / fluctuation_tau_s).exp();
                (phi, fluctuation_c * (1.0 - phi * phi).sqrt())
            }
            Profile::Steps { heater_tau_s, .. } => ((-tau0 / heater_tau_s).exp(), 0.0),
            _ => (0.0, 0.0),
        };
        let mut t = Thermal {
            profile: profile.clone(),
            table,
            cursor: 0,
            tau0,
            state: 0.0,
            fluctuation: 0.0,
            decay,
            kick,
            chamber: 0.0,
            sensor: 0.0,
            lag_decay: if lag_s > 0.0 { (-tau0 / lag_s).exp() } else { 0.0 },
            step: 0,
        };
        // Everything starts in equilibrium at the profile's first value.
        let start = t.chamber_mean(0.0);
        t.state = start;
        t.chamber = start;
        t.sensor = start;
        Ok(t)
    }

    /// The chamber's deterministic temperature at time `t`.
    fn chamber_mean(&mut self, t: f64) -> f64 {
        match &self.profile {
            Profile::Constant { temp_c, .. } => *temp_c,
            Profile::Cooling {
                start_c,
                ambient_c,
                tau_s,
            } => ambient_c + (start_c - ambient_c) * (-t / tau_s).exp(),
            Profile::Ramp {
                from_c,
                to_c,
                duration_s,
            } => from_c + (to_c - from_c) * (t / duration_s).clamp(0.0, 1.0),
            Profile::Steps { levels_c, hold_s, .. } => {
                let i = ((t / hold_s) as usize).min(levels_c.len() - 1);
                levels_c[i]
            }
            Profile::File { .. } => interpolate(&self.table, &mut self.cursor, t),
        }
    }

    /// Advances one sample; returns the sensor's temperature, °C.
    pub fn next(&mut self, rng: &mut impl Rng) -> f64 {
        let t = self.step as f64 * self.tau0;
        self.step += 1;
        let chamber = match &self.profile {
            Profile::Constant { temp_c, .. } => {
                if self.kick > 0.0 {
                    let w: f64 = StandardNormal.sample(rng);
                    self.fluctuation = self.decay * self.fluctuation + self.kick * w;
                }
                temp_c + self.fluctuation
            }
            Profile::Steps { .. } => {
                let target = self.chamber_mean(t);
                self.state = target + (self.state - target) * self.decay;
                self.state
            }
            _ => self.chamber_mean(t),
        };
        self.chamber = chamber;
        self.sensor = chamber + (self.sensor - chamber) * self.lag_decay;
        self.sensor
    }

    /// The chamber's temperature at the last sample, °C.
    pub fn chamber(&self) -> f64 {
        self.chamber
    }
}

fn interpolate(table: &[(f64, f64)], cursor: &mut usize, t: f64) -> f64 {
    // `cursor` is the first row later than the previous t; it only moves on.
    while *cursor < table.len() && table[*cursor].0 <= t {
        *cursor += 1;
    }
    match *cursor {
        0 => table.first().map_or(0.0, |p| p.1),
        i if i == table.len() => table.last().map_or(0.0, |p| p.1),
        i => {
            let (t0, v0) = table[i - 1];
            let (t1, v1) = table[i];
            v0 + (v1 - v0) * (t - t0) / (t1 - t0)
        }
    }
}

fn read_table(path: &std::path::Path) -> Result<Vec<(f64, f64)>, SimError> {
    use std::io::BufRead;
    let at = |line: usize, what: String| SimError::Profile(format!("{}:{line}: {what}", path.display()));
    let file =
        std::fs::File::open(path).map_err(|e| SimError::Profile(format!("{}: {e}", path.display())))?;
    let mut table: Vec<(f64, f64)> = Vec::new();
    let mut header_seen = false;
    for (i, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|e| at(i + 1, e.to_string()))?;
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = l
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let parsed = match fields.as_slice() {
            [t, v] => t.parse::<f64>().ok().zip(v.parse::<f64>().ok()),
            _ => None,
        };
        match parsed {
            Some((t, v)) if t.is_finite() && v.is_finite() => {
                if table.last().is_some_and(|&(tp, _)| t <= tp) {
                    return Err(at(i + 1, format!("time {t} s does not increase")));
                }
                table.push((t, v));
            }
            // One header line is allowed before the first row.
            _ if table.is_empty() && !header_seen => header_seen = true,
            _ => return Err(at(i + 1, format!("expected 'time_s, temp_c', found '{l}'"))),
        }
    }
    if table.is_empty() {
        return Err(SimError::Profile(format!(
            "{}: no rows of 'time_s, temp_c'",
            path.display()
        )));
    }
    Ok(table)
}
