//! Every subcommand and flag of `imutherm`, with its help text, in one place
//! (the examples that close each `--help` are in `help_examples`).
//! Without the `analysis` feature only `record` is built.

#![cfg_attr(not(all(feature = "analysis", feature = "record")), allow(dead_code))]

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

#[cfg(feature = "analysis")]
use allan::{DataType, Stat, TauSpec};
#[cfg(feature = "analysis")]
use thermal::tcal::Order;

use crate::flags::{self, Device};
#[cfg(feature = "record")]
use crate::help_examples::RECORD_EXAMPLES;
#[cfg(feature = "analysis")]
use crate::help_examples::{
    ADEV_EXAMPLES, INFO_EXAMPLES, INS_EXAMPLES, NOISE_EXAMPLES, SIMULATE_EXAMPLES, TCAL_EXPORT_EXAMPLES,
    TCAL_FIT_EXAMPLES, THERMAL_EXAMPLES,
};

/// imutherm — tells the truth about low-cost MEMS IMUs and their temperature
/// dependency: Allan statistics, noise terms, temperature compensation.
#[derive(Debug, Parser)]
#[command(name = "imutherm", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    #[cfg(feature = "analysis")]
    /// Run the thesis's experiment on simulated data: four constant-temperature
    /// runs (34, 43, 62, 82 °C) and a cooling run (100 → 20 °C) of the
    /// mpu9250-thesis preset, noise terms, ADEV over temperature, a compensation
    /// fitted on the cooling run and evaluated on a held-out heating run; writes
    /// DIR/report.html.
    #[command(
        after_help = "Examples:\n  imutherm demo                 full: 1 h runs at 20 Hz\n  imutherm demo --quick --out /tmp/demo\n  imutherm demo --quick --out /tmp/demo-si --units si   every noise figure in rad/s, m/s²\n  imutherm demo --dyn-window 20min --dyn-step 60s   finer dynamic ADEV windows"
    )]
    Demo(DemoArgs),
    #[cfg(feature = "analysis")]
    /// Allan-family deviations (adev, oadev, mdev, tdev, hdev, ohdev, totdev…)
    /// of every column of one or more files, with EDF and confidence intervals.
    #[command(after_help = ADEV_EXAMPLES)]
    Adev(AdevArgs),
    #[cfg(feature = "analysis")]
    /// What is in a recording: channels and units, samples, duration, rate and
    /// jitter, temperature range, per-channel statistics, and every problem
    /// found, with its line.
    #[command(after_help = INFO_EXAMPLES)]
    Info(InfoArgs),
    #[cfg(feature = "analysis")]
    /// Noise terms of each axis (IEEE 952: quantization, angle/velocity random
    /// walk, bias instability, rate random walk, rate ramp) by the slope method
    /// and by a model fit, with intervals and units; a thesis-style table over
    /// the files' temperatures; Kalibr's imu.yaml.
    #[command(after_help = NOISE_EXAMPLES)]
    Noise(NoiseArgs),
    #[cfg(feature = "analysis")]
    /// Simulate an MPU-9250-class IMU recording whose truth is known (IEEE 952
    /// noise terms, bias over temperature, a temperature profile) and write
    /// it as an imutherm log, every true parameter in its metadata.
    #[command(after_help = SIMULATE_EXAMPLES)]
    Simulate(SimulateArgs),
    #[cfg(feature = "analysis")]
    /// The Allan deviation over temperature (the thesis's 3D ADEV): one OADEV
    /// curve per temperature bin or sliding time window, with the noise terms.
    #[command(after_help = THERMAL_EXAMPLES)]
    Thermal(ThermalArgs),
    #[cfg(feature = "analysis")]
    /// Temperature compensation of the bias: fit, apply, evaluate.
    #[command(subcommand)]
    Tcal(TcalCommand),
    /// Record an MPU-9250 through its FIFO into an imutherm log (the thesis
    /// columns plus metadata), losing no sample silently.
    #[command(after_help = RECORD_EXAMPLES)]
    #[cfg(feature = "record")]
    Record(RecordArgs),
    #[cfg(feature = "analysis")]
    /// One self-contained HTML page for a set of recordings: their summaries
    /// and problems, the thesis's noise tables, ADEV plots, and the ADEV over
    /// temperature of runs whose temperature changes.
    #[command(
        after_help = "Examples:\n  imutherm report run_34C.txt run_43C.txt run_62C.txt run_82C.txt cooling.txt --out rep\n  imutherm report cooling.txt --out rep --dyn-window 10min --dyn-step 30s\n  imutherm report run_34C.txt run_43C.txt --out rep-thesis --units thesis   °/√s, °/s as the thesis's tables"
    )]
    Report(ReportArgs),
    #[cfg(feature = "analysis")]
    /// Strapdown navigation of static recordings: how far off a filter
    /// drifts without aiding, from many start points, measured against the
    /// static truth beside the prediction from the noise terms; raw against
    /// temperature-compensated with --model.
    #[command(after_help = INS_EXAMPLES)]
    Ins(InsArgs),
}

#[derive(Debug, Args)]
pub struct RecordArgs {
    /// The sensor: i2c:/dev/i2c-1[@0x68], spi:/dev/spidev0.0 or sim[:PRESET].
    #[arg(long, value_name = "DEVICE", value_parser = flags::device)]
    pub device: Device,

    /// Output rate, Hz (1 kHz / (1 + divider)).
    #[arg(long, default_value_t = 200.0, value_name = "HZ", value_parser = flags::chip_rate)]
    pub rate: f64,

    /// Accelerometer full scale, g (2, 4, 8, 16).
    #[arg(long, default_value_t = 2.0, value_name = "G", value_parser = flags::accel_range())]
    pub accel_range: f64,

    /// Gyroscope full scale, °/s (250, 500, 1000, 2000).
    #[arg(long, default_value_t = 250.0, value_name = "DPS", value_parser = flags::gyro_range())]
    pub gyro_range: f64,

    /// Gyro low-pass bandwidth, Hz (default: the widest below half the rate).
    #[arg(long, value_name = "HZ", value_parser = flags::dlpf())]
    pub dlpf: Option<f64>,

    /// Stop after this long (3600, 90m, 2h…); default: until Ctrl-C.
    #[arg(long, value_name = "D", value_parser = flags::duration)]
    pub duration: Option<f64>,

    /// Output file (imutherm log).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: PathBuf,

    /// Replace FILE if it exists (by default an existing file is an error:
    /// a recording is hours of work).
    #[arg(long)]
    pub overwrite: bool,

    /// Add a column host_time[s]: the Unix time at which the host read each
    /// sample, less its age in the FIFO (readers keep it as a channel and
    /// never use it as the time axis unless named with --time-column).
    #[arg(long)]
    pub host_time: bool,

    /// Simulated device only: fail this fraction of bus transfers (0.01 = 1 %).
    #[arg(long, default_value_t = 0.0, value_name = "RATE", value_parser = flags::error_fraction)]
    pub sim_bus_errors: f64,

    /// Simulated device only: pause reading for 0.5 s every this many
    /// seconds, as a slow host would, so that the FIFO overflows.
    #[arg(long, value_name = "S", value_parser = flags::positive)]
    pub sim_stall_every: Option<f64>,

    /// Simulated device only: a brown-out this many seconds into the run
    /// (the chip's registers return to power-on values and it stops
    /// delivering until configured again).
    #[arg(long, value_name = "S", value_parser = flags::brownout_at)]
    pub sim_brownout_at: Option<f64>,

    /// Simulated device only: the chip's clock error, ppm (a real
    /// MPU-9250 clocked from its gyro varies by ±1 % over temperature,
    /// PS-MPU-9250A-01 §4.15), which the logger measures and reports as
    /// rate_measured_hz.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "PPM",
        allow_hyphen_values = true,
        value_parser = flags::clock_ppm
    )]
    pub sim_clock_ppm: f64,
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Recordings (one per temperature for the tables).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Where to write report.html.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// svg (the plots inline in report.html) or png (also every plot as a
    /// PNG file in DIR/figures).
    #[arg(
        long,
        value_enum,
        default_value = "svg",
        value_name = "svg|png",
        ignore_case = true
    )]
    pub format: FigureFormat,

    /// The datasheet the summary compares with: a built-in part (MPU-9250,
    /// MPU-6050, ICM-20948, BMI088, ADIS16405) or a TOML file in the same
    /// form. None unless given.
    #[arg(long, value_name = "NAME|FILE.toml")]
    pub datasheet: Option<String>,

    #[command(flatten)]
    pub dynamic: DynamicArgs,

    #[command(flatten)]
    pub page_units: PageUnitsArgs,

    #[command(flatten)]
    pub read: ReadArgs,
}

#[cfg(feature = "analysis")]
#[derive(Debug, Args)]
pub struct ThermalArgs {
    /// A recording with a temperature channel.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// Slice by temperature bins or by sliding time windows.
    #[arg(
        long,
        default_value = "temperature",
        value_name = "temperature|time",
        value_enum,
        ignore_case = true
    )]
    pub by: SliceBy,

    /// Width of a temperature bin, °C.
    #[arg(long, default_value_t = 5.0, value_name = "C", value_parser = flags::positive)]
    pub bin_width: f64,

    /// Length of a time window, s.
    #[arg(long, default_value_t = 600.0, value_name = "S", value_parser = flags::positive)]
    pub window: f64,

    /// Step between time windows, s (default: half a window).
    #[arg(long, value_name = "S", value_parser = flags::positive)]
    pub step: Option<f64>,

    /// Channels, as for `adev` (default: the six inertial channels).
    #[arg(long, short = 'c', value_name = "C", value_delimiter = ',')]
    pub channels: Vec<String>,

    #[command(flatten)]
    pub read: ReadArgs,

    /// Confidence level of the intervals.
    #[arg(long, default_value_t = allan::DEFAULT_CONFIDENCE, value_name = "LEVEL", value_parser = flags::confidence)]
    pub confidence: f64,

    /// Print one JSON document (schema imutherm.thermal/1).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Where to write the simulated runs, the model and report.html.
    #[arg(long, default_value = "imutherm-demo", value_name = "DIR")]
    pub out: PathBuf,

    /// Shorter runs at a lower rate: the whole demo in well under a minute.
    #[arg(long)]
    pub quick: bool,

    /// svg (the plots inline in report.html) or png (also every plot as a
    /// PNG file in DIR/figures).
    #[arg(
        long,
        value_enum,
        default_value = "svg",
        value_name = "svg|png",
        ignore_case = true
    )]
    pub format: FigureFormat,

    /// The datasheet the summary compares with: a built-in part (MPU-9250,
    /// MPU-6050, ICM-20948, BMI088, ADIS16405), a TOML file in the same form,
    /// or `none`.
    #[arg(long, default_value = "MPU-9250", value_name = "NAME|FILE.toml|none")]
    pub datasheet: String,

    #[command(flatten)]
    pub dynamic: DynamicArgs,

    #[command(flatten)]
    pub page_units: PageUnitsArgs,
}

/// The dynamic ADEV's windows (the report's 3D ADEV of a run whose
/// temperature changes).
#[derive(Debug, Args)]
pub struct DynamicArgs {
    /// Length of each sliding window of the dynamic ADEV: seconds, or a
    /// number with s, min or h [default: 30min, the thesis's]. A window
    /// longer than the run is an error.
    #[arg(long, value_name = "DURATION", value_parser = flags::duration)]
    pub dyn_window: Option<f64>,

    /// Step between the starts of two windows [default: 90s, the thesis's].
    #[arg(long, value_name = "DURATION", value_parser = flags::duration)]
    pub dyn_step: Option<f64>,
}

#[cfg(feature = "analysis")]
#[derive(Debug, Subcommand)]
pub enum TcalCommand {
    /// Fit the bias of each inertial channel as a polynomial of temperature.
    #[command(after_help = TCAL_FIT_EXAMPLES)]
    Fit(TcalFitArgs),
    /// Apply a model: x_comp = x − (p(T) − p(T_ref)), writing a recording.
    #[command(after_help = "Example:\n  imutherm tcal apply model.json run82.txt -o run82_comp.txt")]
    Apply(TcalApplyArgs),
    /// Residual bias over temperature before and after, on any runs; with
    /// --export, also after the firmware's own correction from the exported
    /// parameters, and the parameter file itself.
    #[command(
        after_help = "Example:\n  imutherm tcal eval model.json heating.txt --export px4 > heating_check.params"
    )]
    Eval(TcalEvalArgs),
    /// Write the model as a flight stack's temperature calibration: PX4's
    /// TC_* parameters in QGroundControl's .params format, or ArduPilot's
    /// INS_TCALn_* as a NAME VALUE .parm file.
    #[command(after_help = TCAL_EXPORT_EXAMPLES)]
    Export(TcalExportArgs),
}

/// The format of the report's figure files besides the page's SVG.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FigureFormat {
    #[value(name = "svg")]
    Svg,
    #[value(name = "png")]
    Png,
}

/// How `thermal` slices a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SliceBy {
    #[value(name = "temperature", alias = "temp")]
    Temperature,
    #[value(name = "time")]
    Time,
}

/// The units `noise` prints its terms in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TermUnits {
    #[value(name = "si")]
    Si,
    #[value(name = "datasheet")]
    Datasheet,
}

/// The one unit system of a report page's noise figures: `noise --units`'s
/// vocabulary, with the thesis's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PageUnits {
    #[value(name = "si")]
    Si,
    #[value(name = "datasheet")]
    Datasheet,
    #[value(name = "thesis")]
    Thesis,
}

/// The page's units flag, shared by `report` and `demo`.
#[derive(Debug, Args)]
pub struct PageUnitsArgs {
    /// One unit system for every noise figure of the page (summary, answer,
    /// thesis tables, ADEV charts, each axis's noise-model figure): datasheet
    /// (°/s/√Hz, °/h, °/h/√h, °/s/°C; µg/√Hz, µg, µg/√s, mg/°C: the units the
    /// summary's datasheet column is in), si (rad/√s, rad/s, rad/s/√s;
    /// m/s/√s, m/s², m/s²/√s) or thesis (°/√s, °/s, °/s/√s; SI for
    /// accelerometers). The heat maps, 3D views, compensation and raw-data
    /// plots stay in the channel's SI unit.
    #[arg(
        long,
        value_enum,
        default_value = "datasheet",
        value_name = "datasheet|si|thesis",
        ignore_case = true
    )]
    pub units: PageUnits,
}

/// A flight stack imutherm writes temperature calibrations for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FirmwareArg {
    /// PX4: TC_* parameters, QGroundControl .params file.
    #[value(name = "px4")]
    Px4,
    /// ArduPilot: INS_TCALn_* parameters, NAME VALUE .parm file.
    #[value(name = "ardupilot")]
    ArduPilot,
}

/// A device id: decimal (as PX4 shows it) or 0x-prefixed hexadecimal.
fn device_id(text: &str) -> Result<u32, String> {
    let t = text.trim();
    let parsed = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => t.parse::<u32>(),
    };
    parsed.map_err(|_| format!("'{text}' is not a device id (a number from 0 to 4294967295, or 0x…)"))
}

#[derive(Debug, Args)]
pub struct TcalExportArgs {
    /// The model from `tcal fit`.
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,

    /// The flight stack to write for.
    #[arg(
        long,
        value_enum,
        value_name = "px4|ardupilot",
        required_unless_present = "format"
    )]
    pub firmware: Option<FirmwareArg>,

    /// Write the model as a C header instead (`c`): its coefficients and one
    /// reference function compensating a sample as `tcal apply` does.
    #[arg(long, value_name = "c", value_parser = ["c"], conflicts_with_all = ["firmware", "slot", "device_id"])]
    pub format: Option<String>,

    /// Where to write the parameter file (default: standard output).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Replace FILE if it exists.
    #[arg(long, requires = "output")]
    pub overwrite: bool,

    /// The firmware's calibration slot: PX4 0 to 3 (default 0), ArduPilot's
    /// IMU 1 to 3 (default 1). Not the log's `--instance` a reading takes:
    /// `--instance` here is kept, hidden, as this flag's former name.
    #[arg(long, value_name = "N", alias = "instance", value_parser = clap::value_parser!(u8).range(0..=3))]
    pub slot: Option<u8>,

    /// The sensor's device id (PX4: `listener sensor_gyro`, or CAL_GYRO0_ID),
    /// decimal or 0x-hex; default: the one the recording carried.
    #[arg(long, value_name = "ID", value_parser = device_id)]
    pub device_id: Option<u32>,
}

#[cfg(feature = "analysis")]
#[derive(Debug, Args)]
pub struct TcalFitArgs {
    /// Runs to fit (same channels in each).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Polynomial order, or auto.
    #[arg(long, default_value = "auto", value_name = "N|auto", value_parser = flags::order)]
    pub order: Order,

    /// Reference temperature, °C (default: the middle of the fitted range).
    #[arg(long, value_name = "C", value_parser = flags::temperature)]
    pub tref: Option<f64>,

    /// Also fit a term in dT/dt (thermal lag: heating against cooling).
    #[arg(long)]
    pub rate_term: bool,

    /// Fit what this flight stack can load: --order auto stops at a cubic,
    /// a higher --order and --rate-term are refused.
    #[arg(
        long = "for",
        value_enum,
        value_name = "px4|ardupilot",
        conflicts_with = "rate_term"
    )]
    pub for_firmware: Option<FirmwareArg>,

    /// Width of the averaging bins, °C.
    #[arg(long, default_value_t = 1.0, value_name = "C", value_parser = flags::positive)]
    pub bin_width: f64,

    /// Channels (default: the six inertial channels).
    #[arg(long, short = 'c', value_name = "C", value_delimiter = ',')]
    pub channels: Vec<String>,

    #[command(flatten)]
    pub read: ReadArgs,

    #[command(flatten)]
    pub motion: MotionArgs,

    /// Where to write the model (JSON, schema imutherm.tcal/1).
    #[arg(long, short = 'o', value_name = "MODEL.json")]
    pub output: PathBuf,

    /// Replace the output if it exists (by default an existing file is an
    /// error; an input is never replaced).
    #[arg(long)]
    pub overwrite: bool,
}

#[derive(Debug, Args)]
pub struct TcalApplyArgs {
    /// The model from `tcal fit`.
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,

    /// The recording to compensate.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    #[command(flatten)]
    pub read: ReadArgs,

    /// Output recording (imutherm log).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: PathBuf,

    /// Replace the output if it exists (by default an existing file is an
    /// error; an input is never replaced).
    #[arg(long)]
    pub overwrite: bool,
}

#[derive(Debug, Args)]
pub struct TcalEvalArgs {
    /// The model from `tcal fit`.
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,

    /// Runs to evaluate on (best: runs the fit did not see); at least one.
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,

    #[command(flatten)]
    pub read: ReadArgs,

    #[command(flatten)]
    pub motion: MotionArgs,

    /// Also apply the exported parameters as the firmware does and show the
    /// bias left; print the parameter file, with the table as comments.
    #[arg(long, value_enum, value_name = "px4|ardupilot", ignore_case = true)]
    pub export: Option<FirmwareArg>,

    /// With --export: apply this parameter file (a PX4 .params, an ArduPilot
    /// .parm, as loaded into the vehicle) instead of the model's own export,
    /// and do not print parameters.
    #[arg(long, value_name = "FILE", requires = "export")]
    pub params: Option<PathBuf>,

    /// Print one JSON document (schema imutherm.tcal-eval/1).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// A TOML configuration (see --print-config for the full form).
    #[arg(long, value_name = "FILE", conflicts_with = "preset")]
    pub config: Option<PathBuf>,

    /// A named configuration: mpu9250-thesis (default) or white.
    #[arg(long, value_name = "P")]
    pub preset: Option<String>,

    /// Chamber temperature profile, overriding the configuration's.
    #[arg(long, value_name = "SPEC")]
    pub profile: Option<String>,

    /// Duration (3600, 90m, 2h…), overriding the configuration's.
    #[arg(long, value_name = "D", value_parser = flags::duration)]
    pub duration: Option<f64>,

    /// Sample rate in Hz, overriding the configuration's.
    #[arg(long, value_name = "HZ", value_parser = flags::positive)]
    pub rate: Option<f64>,

    /// Seed of the random streams, overriding the configuration's.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,

    /// Draw the production unit ID (its serial number) of a population
    /// around the configuration: its noise terms and bias polynomials
    /// scatter (see --scatter), fixed by the id; the seed still picks the
    /// run's noise realisation. (`--unit`, this flag's former name, is kept
    /// hidden; elsewhere `--unit` is a column's unit.)
    #[arg(long, value_name = "ID", alias = "unit")]
    pub unit_id: Option<String>,

    /// The population's relative spread NOISE,BIAS (one standard deviation:
    /// log-normal on every noise term, normal on every bias coefficient).
    #[arg(
        long,
        value_name = "NOISE,BIAS",
        default_value = "0.1,0.2",
        requires = "unit_id"
    )]
    pub scatter: String,

    /// Plant a fault in the unit: noise-3x (every noise term ×3), slope-5x
    /// (bias slope 5× the population's) or dead-axis[:CHANNEL] (gyro_z by
    /// default: a constant output).
    #[arg(long, value_name = "DEFECT", requires = "unit_id")]
    pub defect: Option<String>,

    /// Output file (imutherm log format).
    #[arg(
        long,
        short = 'o',
        value_name = "FILE",
        required_unless_present = "print_config"
    )]
    pub output: Option<PathBuf>,

    /// Print the effective configuration as TOML and exit.
    #[arg(long)]
    pub print_config: bool,

    /// Replace the output if it exists (by default an existing file is an
    /// error; an input is never replaced).
    #[arg(long)]
    pub overwrite: bool,

    /// Write a recording of more than 100 million values (rows × 7 columns,
    /// about 2 GB), which is otherwise refused as a likely mistake.
    #[arg(long)]
    pub allow_large: bool,
}

#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// Recordings (one per temperature for the thesis table).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Channels, as for `adev` (default: the six inertial channels).
    #[arg(long, short = 'c', value_name = "C", value_delimiter = ',')]
    pub channels: Vec<String>,

    #[command(flatten)]
    pub read: ReadArgs,

    #[command(flatten)]
    pub motion: MotionArgs,

    /// Units of the printed terms: si (rad/√s, rad/s, rad/s/√s; m/s/√s, m/s²,
    /// m/s²/√s) or datasheet (°/√h, °/h, °/h/√h; m/s/√h, µg, µg/√s) — the thesis
    /// table uses °/√s and °/s for gyros in both.
    #[arg(
        long,
        value_enum,
        default_value = "si",
        value_name = "si|datasheet",
        ignore_case = true
    )]
    pub units: TermUnits,

    /// Confidence level of the intervals (fraction or percentage).
    #[arg(long, default_value_t = 0.95, value_name = "LEVEL", value_parser = flags::confidence)]
    pub confidence: f64,

    /// Also write Kalibr's imu.yaml (noise densities and random walks of the
    /// worst axis, per-axis values in comments).
    #[arg(long, value_name = "FILE")]
    pub kalibr: Option<PathBuf>,

    /// Replace the --kalibr file if it exists (by default an existing file
    /// is an error; an input is never replaced).
    #[arg(long)]
    pub overwrite: bool,

    /// Print one JSON document (schema imutherm.noise/1).
    #[arg(long)]
    pub json: bool,

    /// Print both methods' full detail per channel (the slope method's
    /// stretches, the fit's points left out, every reason), not only the
    /// compact table.
    #[arg(long, short = 'v')]
    pub verbose: bool,
}

/// Options on how a recording is read, shared by the commands that read one.
#[derive(Debug, Args)]
pub struct ReadArgs {
    /// Sample rate in Hz, overriding the file's metadata (`# sample_rate_hz:`)
    /// or time column. Without any of them: 1 Hz, with a note.
    #[arg(long, short = 'r', value_name = "HZ", value_parser = flags::positive)]
    pub rate: Option<f64>,

    /// Unit of a column, overriding its header, converted to SI on reading:
    /// `--unit gyro_x=deg/s` (repeatable).
    #[arg(long, value_name = "COL=UNIT", value_parser = flags::unit_override)]
    pub unit: Vec<imu::units::UnitOverride>,

    /// Multiply a column's values by a factor before its unit converts them:
    /// `--scale col2=4` (repeatable), for a firmware that prints with the
    /// wrong sensitivity. Said in the notes.
    #[arg(long, value_name = "COL=FACTOR", value_parser = flags::column_scale)]
    pub scale: Vec<imu::units::ColumnScale>,

    /// The time column (default: one named time, timestamp or t, or with a
    /// time unit in its header).
    #[arg(long, value_name = "NAME")]
    pub time_column: Option<String>,

    /// Unit of the time column when its header has none: s, ms, us or ns.
    #[arg(long, value_name = "UNIT", value_parser = flags::time_unit)]
    pub time_unit: Option<String>,

    /// Skip malformed rows instead of stopping: each becomes a gap and is
    /// reported with its line.
    #[arg(long)]
    pub skip_bad_lines: bool,

    /// The IMU topic of a ROS bag (or a stream of `info`'s list, such as
    /// sensor_combined); needed when the log has several.
    #[arg(long, value_name = "NAME")]
    pub topic: Option<String>,

    /// The IMU instance of a PX4 ULog or ArduPilot DataFlash log; `all`
    /// (tcal fit and tcal eval) takes every instance at once.
    #[arg(long, value_name = "N|all", value_parser = flags::instance)]
    pub instance: Option<flags::Instance>,

    /// The sensor_msgs/Temperature topic of a ROS bag, matched by time to
    /// the IMU (default: the only one).
    #[arg(long, value_name = "NAME")]
    pub temp_topic: Option<String>,

    /// How far gaps may stretch the time grid, as a multiple of the samples
    /// (default 16; beyond it the time column is taken for wrong). Raise it
    /// to read a duty-cycled log, such as 5 s logged every 305 s (61), with
    /// its gaps.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub max_grid_factor: Option<u32>,

    /// Read a ROS 2 bag whose metadata.yaml lists storage files that are
    /// missing from the files that are there; each missing file is reported
    /// as a problem with the messages the metadata gives it.
    #[arg(long)]
    pub allow_partial: bool,
}

/// For the analyses of a static sensor (`noise`, `ins`, `tcal fit`,
/// `tcal eval`).
#[derive(Debug, Args)]
pub struct MotionArgs {
    /// Analyse a record that moves: without it, a record whose gyro or
    /// accelerometer scatters far above its noise floor or changes level
    /// is refused, with the stretches that move.
    #[arg(long)]
    pub allow_motion: bool,
}

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Recordings: thesis or imutherm logs, or numeric columns with a header.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    #[command(flatten)]
    pub read: ReadArgs,

    /// Print one JSON document (schema imutherm.info/1).
    #[arg(long)]
    pub json: bool,
}

#[cfg(feature = "analysis")]
#[derive(Debug, Args)]
pub struct AdevArgs {
    /// Input files (plain numeric columns; .gz read transparently).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Statistic: adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev,
    /// ttotdev, htotdev or theo1 (mtotdev/ttotdev/htotdev/theo1 without bias
    /// correction, as Stable32 and AllanTools print them).
    #[arg(long, short = 's', default_value = "oadev", value_name = "S", value_parser = flags::stat())]
    pub stat: Stat,

    /// Tau grid: octave, decade, all, many (log-spaced, 50 per decade), or a
    /// comma list of taus in seconds. Taus the data cannot support are dropped.
    #[arg(long, short = 't', default_value = "octave", value_name = "T", value_parser = flags::taus)]
    pub taus: TauSpec,

    /// Channels to analyse, comma separated: imutherm names (gyro_x, accel_z),
    /// header names, 1-based column indices, or the groups gyro, accel,
    /// inertial, all. Default: the six inertial channels of an IMU file, else
    /// every column.
    #[arg(long, short = 'c', value_name = "C", value_delimiter = ',')]
    pub channels: Vec<String>,

    #[command(flatten)]
    pub read: ReadArgs,

    /// What the samples are: freq (rate samples, as an IMU gives) or phase
    /// (integrated samples).
    #[arg(long, default_value = "freq", value_name = "freq|phase", value_parser = flags::data_type())]
    pub data_type: DataType,

    /// Confidence level of the intervals, as a fraction (0.683) or a
    /// percentage (68.3).
    #[arg(long, default_value_t = allan::DEFAULT_CONFIDENCE, value_name = "LEVEL", value_parser = flags::confidence)]
    pub confidence: f64,

    /// Print one JSON document (schema imutherm.adev/1) instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// A positive number of seconds.
fn seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{text}' is not a positive number of seconds")),
    }
}

/// A geodetic latitude in degrees.
fn latitude(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v.abs() <= 90.0 => Ok(v),
        _ => Err(format!("'{text}' is not a latitude from -90 to 90 degrees")),
    }
}

#[derive(Debug, Args)]
pub struct InsArgs {
    /// Static recordings with the six inertial channels.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Alignment window at the start of each window, s.
    #[arg(long, default_value = "10", value_name = "S", value_parser = seconds)]
    pub align: f64,

    /// How long each window is navigated after its alignment, s.
    #[arg(long, default_value = "120", value_name = "S", value_parser = seconds)]
    pub horizon: f64,

    /// Start a window every this many seconds.
    #[arg(long, default_value = "10", value_name = "S", value_parser = seconds)]
    pub every: f64,

    /// Geodetic latitude, degrees: normal gravity, Earth rate and Coriolis.
    #[arg(long, value_name = "DEG", value_parser = latitude, allow_hyphen_values = true)]
    pub latitude: Option<f64>,

    /// Also navigate each recording compensated with this model (from
    /// `tcal fit`), beside the raw one; both predicted from the compensated
    /// run's noise terms.
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<PathBuf>,

    /// Runs of the Monte Carlo (its rms to ±1/(2·√N), 1σ), up to 100000.
    #[arg(long, default_value = "700", value_name = "N", value_parser = clap::value_parser!(u32).range(2..=100_000))]
    pub runs: u32,

    /// Seed of the Monte Carlo's first run.
    #[arg(long, default_value = "1", value_name = "N")]
    pub seed: u64,

    /// Also draw the error against time (measured, predicted, Monte Carlo
    /// band; raw and compensated) to this file: .svg or .png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    #[command(flatten)]
    pub read: ReadArgs,

    #[command(flatten)]
    pub motion: MotionArgs,

    /// Print one JSON document (schema imutherm.ins/1).
    #[arg(long)]
    pub json: bool,
}

/// Ends the program as a usage error (status 2), as clap does for a bad
/// flag: for what only becomes wrong in combination with another flag.
pub fn usage_error(message: impl std::fmt::Display) -> ! {
    use clap::CommandFactory;
    Cli::command()
        .error(clap::error::ErrorKind::ValueValidation, message)
        .exit()
}

#[cfg(test)]
mod tests {
    use super::Cli;

    /// The whole command line, its defaults included, is well formed
    /// (clap's own consistency checks).
    #[test]
    fn the_command_line_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }

    /// Words the command line is made of, to build argument lists from.
    const WORDS: &[&str] = &[
        "adev",
        "info",
        "noise",
        "thermal",
        "tcal",
        "fit",
        "apply",
        "eval",
        "simulate",
        "record",
        "report",
        "demo",
        "--stat",
        "--taus",
        "--confidence",
        "--rate",
        "-r",
        "--unit",
        "--time-unit",
        "--by",
        "--bin-width",
        "--window",
        "--step",
        "--order",
        "--tref",
        "--export",
        "--device",
        "--dlpf",
        "--accel-range",
        "--gyro-range",
        "--duration",
        "--sim-bus-errors",
        "--sim-clock-ppm",
        "--format",
        "--units",
        "--data-type",
        "-o",
        "--out",
        "--json",
        "--help",
        "-h",
        "--version",
        "x.txt",
        "1",
        "0",
        "-1",
        "1e309",
        "nan",
        "68.3",
        "0.683",
        "auto",
        "9",
        "10",
        "sim:counter",
        "i2c@0x69",
        "time",
        "temp",
        "oadev",
        "many",
        "1,2,3",
        "gyro_x=deg/s",
        "2h",
        "=",
        ",",
        "",
        "--",
        "-",
    ];

    use proptest::strategy::Strategy as _;

    proptest::proptest! {
        /// Any argument list is parsed or refused, never a panic.
        #[test]
        fn any_arguments_are_parsed_or_refused(
            args in proptest::collection::vec(
                proptest::prop_oneof![
                    proptest::sample::select(WORDS).prop_map(str::to_string),
                    ".{0,12}",
                ],
                0..12,
            )
        ) {
            use clap::Parser;
            let _ = Cli::try_parse_from(std::iter::once("imutherm".to_string()).chain(args));
        }
    }
}
