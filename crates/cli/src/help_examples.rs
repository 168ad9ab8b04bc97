//! The examples each subcommand's `--help` ends with.

#[cfg(feature = "record")]
pub(crate) const RECORD_EXAMPLES: &str = "\
Examples:
  imutherm record --device sim --rate 200 --duration 10s -o test.txt
  imutherm record --device sim:white --rate 100 --duration 5s -o long.txt   (a real run: --duration 1h)

Devices: i2c:/dev/i2c-1[@0x68|@0x69] (≤ 400 kHz: below 500 Hz only on a Pi 3; `i2c` alone is
/dev/i2c-1 at 0x68), spi:/dev/spidev0.0 (1 MHz, mode 0; `spi` alone is /dev/spidev0.0), or sim[:PRESET] (a register-level simulated chip fed by the simulator;
presets mpu9250-thesis, white, and counter: sample k reads k LSB on every field).
--rate is rounded to what the chip makes, 1000/(1 + n) Hz, and the recorded rate is said.
--duration counts samples: 10s at 200 Hz is 2000 rows, gaps included (a run also ends at
1.05 × the duration + 2 s of host time, stopped_by=time_limit, should the chip fall silent).
Ctrl-C or SIGTERM stops cleanly: every sample read is written, the file ends with a
complete line and a trailer (# trailer: samples=… gap_samples=… overflows=… bus_errors=…
rate_measured_hz=…). A lost stretch (FIFO overflow, a read broken off, a stalled sensor)
is a '# gap:' line with its size and cause followed by that many rows of nan, which every
imutherm reader treats as gaps; its size is estimated from host time to ±1 sample.
Status: a line on stderr, redrawn every second on a terminal, once a minute otherwise.";

#[cfg(feature = "analysis")]
pub(crate) const THERMAL_EXAMPLES: &str = "\
Examples:
  imutherm thermal cooling.txt                          5 °C bins
  imutherm thermal cooling.txt --bin-width 2 --channels gyro --json > surface.json
  imutherm thermal cooling.txt --by time --window 600 --step 300

A temperature bin keeps the samples taken while the temperature was inside it; the
rest are gaps, so no Allan term joins two visits to the bin. A time window is labelled
with its mean temperature and its temperature change. A slice left with fewer than 64
samples has no row; it is listed, with the reason, under `skipped` (--json) or the table.";

#[cfg(feature = "analysis")]
pub(crate) const TCAL_EXPORT_EXAMPLES: &str = "\
Examples:
  imutherm tcal export model.json --firmware px4 --device-id 2293768 -o imu.params
  imutherm tcal export model.json --firmware ardupilot --slot 1 -o imu.parm

Both firmwares take a cubic without a dT/dt term: fit with `tcal fit --for px4|ardupilot`.
PX4 maps the calibration to a sensor by its device id (`listener sensor_gyro`, or the
parameter CAL_GYRO0_ID); without --device-id, and when the model does not carry one,
TC_G0_ID/TC_A0_ID are written as a commented placeholder. Check the file on a run before
flashing with `tcal eval MODEL.json RUN --export px4|ardupilot`.";

#[cfg(feature = "analysis")]
pub(crate) const TCAL_FIT_EXAMPLES: &str = "\
Examples:
  imutherm tcal fit cooling.txt --for px4 -o model.json   a cubic PX4 loads; then:
  imutherm tcal export model.json --firmware px4 -o px4.params
  imutherm tcal fit cooling.txt -o model_auto.json        order by cross-validation (any firmware: none)
  imutherm tcal fit cooling.txt heating.txt --order 3 --tref 25 --rate-term -o model_rate.json

The data are averaged into temperature bins (--bin-width, separately for heating and
cooling) before the least-squares fit on a scaled temperature, so the slow end of a
cooling run does not outweigh the rest. --order auto leaves out one run at a time (or
five contiguous blocks of a single run) and keeps the smallest order within 5 % of the
best held-out RMS.";

#[cfg(feature = "analysis")]
pub(crate) const SIMULATE_EXAMPLES: &str = "\
Examples:
  imutherm simulate -o run34.txt                       the thesis preset: 1 h at 20 Hz, 34 °C
  imutherm simulate --profile constant:82 --seed 4 -o run82.txt
  imutherm simulate --profile cooling:100:20:1800 --duration 3h -o cooling.txt
  imutherm simulate --preset mpu9250-thesis --print-config > my.toml   then edit, and:
  imutherm simulate --config my.toml -o custom.txt

Profiles (°C and seconds; the die follows the chamber with the configuration's sensor_lag_s):
  constant:T[:FLUCTUATION]   cooling:START:AMBIENT:TAU_S   ramp:FROM:TO:DURATION_S
  steps:T1,T2,…:HOLD_S (heater time constant 120 s)   file:PATH (rows of time_s, temp_c)
Durations: 3600, 3600s, 90m, 2h, 1.5h. Presets: mpu9250-thesis, white.

A production line (--unit-id ID: the same board on every run; --seed varies the realisation):
  imutherm simulate --unit-id SN-0042 --duration 20m --profile constant:34 -o SN-0042_static.txt
  imutherm simulate --unit-id SN-0042 --seed 2 --profile ramp:20:80:3600 -o SN-0042_ramp.txt
  imutherm simulate --unit-id SN-0007 --defect noise-3x -o bad.txt     also slope-5x, dead-axis:gyro_z";

#[cfg(feature = "analysis")]
pub(crate) const NOISE_EXAMPLES: &str = "\
Examples:
  imutherm noise imu_34C.txt
  imutherm noise imu_34C.txt imu_43C.txt imu_62C.txt imu_82C.txt --units datasheet
      per-axis terms, then one table per term: rows = axes, columns = temperatures
  imutherm noise imu_34C.txt --kalibr imu.yaml --json > noise.json

What the numbers mean (IEEE Std 952-1997 Annex C, on the overlapping ADEV):
  N  white noise (ARW/VRW): σ(1 s) on the −1/2 line. SI rad/√s = rad/s/√Hz (gyro),
     m/s/√s = m/s²/√Hz (accel). A continuous-time density, as Kalibr's *_noise_density;
     the per-sample standard deviation is N·√rate.
  B  bias instability: σ_min / 0.664 (σ_min, the raw ADEV minimum, is printed too,
     with its τ, as the thesis tables quote it). rad/s, m/s².
  K  rate random walk: σ(3 s) on the +1/2 line. rad/s/√s, m/s²/√s (Kalibr's *_random_walk).
  Q  quantization: σ(√3 s) on the −1 line. R  rate ramp: σ(√2 s) on the +1 line.
One estimator (README, The noise model): the theoretical Allan variance of a sum of
processes, Q, N, B, K, R and up to two first-order Gauss–Markov processes GM (σ, T), fitted to
the octave OADEV by least squares on ln σ̂², weighted by the inverse covariance of the points;
the Bayesian information criterion chooses which processes the data hold. A process enters
only where it carries half the variance at two or more points of 10 degrees of freedom, and
none may rise above the measured 99 % interval. A process the data do not hold is printed as
`≤` its upper bound, never as a value. Each axis says its model (`N + K + GM`), χ²/dof and its
p-value; below p = 0.01 it says no candidate fits. Intervals: the weighted fit's spread under
the points' own covariance (a sandwich estimate).";

#[cfg(feature = "analysis")]
pub(crate) const INFO_EXAMPLES: &str = "\
Examples:
  imutherm info imu_34C.txt
  imutherm info run1.txt.gz run2.txt --json > info.json
  imutherm info phone.csv --time-column t --time-unit ns --unit gyro_x=deg/s

Problems are reported, not fatal, where the data can be kept honestly: NaN and
infinite samples are gaps, a truncated last line is dropped, rows out of time order
are dropped, missing timestamps become gaps. A malformed row stops the reading
unless --skip-bad-lines makes it a gap.";

#[cfg(feature = "analysis")]
pub(crate) const ADEV_EXAMPLES: &str = "\
Examples:
  imutherm adev gyro.txt --rate 200
      overlapping ADEV of every column, octave taus, 68.3 % intervals
  imutherm adev log.csv --channels gyro_x,3 --stat mdev --taus many --json > mdev.json
  imutherm adev imu_log.txt --channels gyro --unit gyro_x=deg/s
  imutherm adev phase.dat --data-type phase --taus 1,10,100 --stat totdev

Input: the thesis/imutherm IMU log, or plain numeric columns separated by commas,
tabs or spaces, with an optional header line and '#' comment lines; gzip files are
read as they are. Units in header brackets (gyro_x[deg/s]) are converted to SI. NaN cells are
gaps: adev, oadev, mdev, tdev, hdev and ohdev skip the terms that cross them.
Rate data (--data-type freq, the default) is what an IMU gives: the deviation is
in the unit of the data (rad/s, m/s², or fractional frequency).";

#[cfg(feature = "analysis")]
pub(crate) const INS_EXAMPLES: &str = "\
Examples:
  imutherm ins run34.txt
  imutherm ins cooling.txt --model model.json --horizon 60
      60 s without GNSS: raw … m, compensated … m
  imutherm ins run34.txt --align 30 --every 60 --latitude 48.1 --json > ins.json

Each window is levelled on its first --align seconds (roll and pitch from the mean
specific force; heading 0, the sensor's x taken as north: a MEMS gyro cannot gyrocompass;
the gyro's mean over the window, less the Earth's rate with --latitude, taken as its
bias, as a filter at rest estimates it), then navigated for --horizon seconds. The truth
is static, so every metre is error. Errors: RMS, median and 95th percentile over the
windows. Predicted: the horizontal position DRMS (2-D rms) from the noise terms (N, B, K of
each axis, identified as `noise` does, on the compensated run with --model) in closed
form, summed in quadrature; bias instability bounded from its 1/f spectrum. Monte
Carlo: the same model simulated and navigated --runs times, its rms with a 95 %
interval; the output says from which time the closed form leaves it by over 10 %.
Without --latitude: standard gravity, no Earth rotation (at rest, the gyro mean removes
it) and no Schuler loop, which holds to 1/ω_s = 806 s: a longer --horizon needs
--latitude. With it: Somigliana's normal gravity, Earth rate, transport rate (the
Schuler loop, in the closed form too), Coriolis.";
