//! From decoded streams to an [`imu::Recording`]: the stream chosen, its
//! time source decided, its samples placed on its clock by
//! [`imu::timing`] exactly as a text log's time column is, and the
//! temperature matched by time.

use std::path::Path;

use imu::timing::{analyze_timestamps, regularize_gapped};
use imu::{Axis, Channel, Problem, ProblemKind, Quantity, ReadReport, Recording, Setting, Value};

use crate::error::{LogError, LogErrorKind, RateTooHigh};
use crate::streams::{Decoded, ImuStream, TempSource, TempStream, mean_rate};

/// Which stream to read, as the command line says.
#[derive(Debug, Clone, Default)]
pub struct Choice {
    /// A ROS topic or a stream name (`sensor_combined`).
    pub topic: Option<String>,
    /// A PX4/ArduPilot instance.
    pub instance: Option<u32>,
    /// The temperature topic.
    pub temp_topic: Option<String>,
    /// With several IMU streams and none chosen, take the first instead of
    /// failing (for `info`, which lists them all anyway).
    pub first_if_several: bool,
    /// Sample rate overriding the stamps' clock, Hz.
    pub rate_hz: Option<f64>,
    /// Largest time grid as a multiple of the samples; `None`:
    /// [`imu::timing::MAX_GRID_FACTOR`].
    pub max_grid_factor: Option<usize>,
    /// Read a ROS 2 bag whose `metadata.yaml` lists files that are missing
    /// from those that are there, reporting the loss, instead of refusing.
    pub allow_partial: bool,
}

/// One stream found in a log, for `info`.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamInfo {
    /// Topic or instance name.
    pub name: String,
    /// `imu` or `temperature`.
    pub kind: &'static str,
    /// The PX4/ArduPilot instance.
    pub instance: Option<u32>,
    /// Message type.
    pub msg_type: String,
    /// Messages in the log.
    pub messages: usize,
    /// Mean rate over the log's time, Hz.
    pub rate_hz: Option<f64>,
    /// The rate between consecutive messages (one over their median step),
    /// Hz: what the clock reads where the stream flows, which the mean
    /// undercuts by the gaps' share of the span.
    pub step_rate_hz: Option<f64>,
    /// Where an IMU stream's temperature comes from.
    pub temperature: String,
    /// Whether this stream is the one read.
    pub selected: bool,
}

/// Why a stream is not offered by default (a per-sensor topic logged below
/// full rate, or `sensor_combined` beside full-rate per-sensor topics).
pub(crate) fn is_default_candidate(s: &ImuStream, all: &[ImuStream]) -> bool {
    let combined = all.iter().find(|x| x.name == "sensor_combined");
    // A per-sensor topic subscribed but (almost) never written holds no
    // data to offer: it must not hide the stream that does.
    let per_sensor: Vec<&ImuStream> = all
        .iter()
        .filter(|x| x.name.starts_with("sensor_gyro/") && !x.is_empty())
        .collect();
    let full_rate = |g: &ImuStream| match (g.mean_rate_hz(), combined.and_then(ImuStream::mean_rate_hz)) {
        (Some(a), Some(b)) => a >= 0.9 * b,
        (None, Some(_)) => false,
        _ => true,
    };
    if s.name == "sensor_combined" {
        return !per_sensor.iter().any(|g| full_rate(g));
    }
    if s.name.starts_with("sensor_gyro/") {
        return full_rate(s);
    }
    true
}

fn describe(s: &ImuStream) -> String {
    let rate = s.mean_rate_hz().map_or("rate unknown".to_string(), |r| {
        format!("{} Hz", imu::log_file::round_rate(r))
    });
    format!("{} ({} messages, {rate})", s.name, s.len())
}

/// Picks the IMU stream.
fn choose(path: &Path, d: &Decoded, c: &Choice) -> Result<usize, LogError> {
    let list = || d.imu.iter().map(describe).collect::<Vec<_>>().join("; ");
    if d.imu.iter().all(ImuStream::is_empty) {
        return Err(LogError::new(path, LogErrorKind::NoImuStream));
    }
    if let Some(t) = &c.topic {
        return d.imu.iter().position(|s| &s.name == t).ok_or_else(|| {
            LogError::new(
                path,
                LogErrorKind::NoSuchStream {
                    wanted: Setting::Topic.given(Value::text(t.as_str())),
                    list: list(),
                },
            )
        });
    }
    if let Some(i) = c.instance {
        let found: Vec<usize> = (0..d.imu.len())
            .filter(|&k| d.imu[k].instance == Some(i))
            .collect();
        return found
            .iter()
            .find(|&&k| is_default_candidate(&d.imu[k], &d.imu))
            .or(found.first())
            .copied()
            .ok_or_else(|| {
                LogError::new(
                    path,
                    LogErrorKind::NoSuchStream {
                        wanted: Setting::Instance.given(Value::number(i)),
                        list: list(),
                    },
                )
            });
    }
    let candidates: Vec<usize> = (0..d.imu.len())
        .filter(|&k| !d.imu[k].is_empty() && is_default_candidate(&d.imu[k], &d.imu))
        .collect();
    match candidates.as_slice() {
        [one] => Ok(*one),
        [first, ..] if c.first_if_several => Ok(*first),
        [] => Err(LogError::new(path, LogErrorKind::NoImuStream)),
        many => {
            let setting = if many.iter().all(|&k| d.imu[k].instance.is_some()) {
                Setting::Instance
            } else {
                Setting::Topic
            };
            Err(LogError::new(
                path,
                LogErrorKind::SeveralStreams {
                    count: many.len(),
                    kind: "IMU",
                    setting,
                    list: many
                        .iter()
                        .map(|&k| describe(&d.imu[k]))
                        .collect::<Vec<_>>()
                        .join("; "),
                },
            ))
        }
    }
}

/// Picks the temperature topic: the one asked for, or the only one.
fn choose_temp<'a>(path: &Path, d: &'a Decoded, c: &Choice) -> Result<Option<&'a TempStream>, LogError> {
    let list = || {
        d.temps
            .iter()
            .map(|t| t.name.clone())
            .collect::<Vec<_>>()
            .join(", ")
    };
    match &c.temp_topic {
        Some(t) => d.temps.iter().find(|s| &s.name == t).map(Some).ok_or_else(|| {
            LogError::new(
                path,
                LogErrorKind::NoSuchStream {
                    wanted: Setting::TempTopic.given(Value::text(t.as_str())),
                    list: if d.temps.is_empty() { "none".into() } else { list() },
                },
            )
        }),
        None => match d.temps.as_slice() {
            [one] => Ok(Some(one)),
            [] => Ok(None),
            _ => Err(LogError::new(
                path,
                LogErrorKind::SeveralStreams {
                    count: d.temps.len(),
                    kind: "temperature",
                    setting: Setting::TempTopic,
                    list: list(),
                },
            )),
        },
    }
}

/// The times to use, which they are, and why.
fn time_source(s: &mut ImuStream) -> (Vec<f64>, bool, String) {
    // Readers mark a stamp that is zero, negative or NaN as NaN.
    let zero = s.stamp.iter().filter(|v| !v.is_finite()).count();
    if zero == 0 && !s.stamp.is_empty() {
        (
            std::mem::take(&mut s.stamp),
            true,
            format!("{}: every message has one", s.stamp_name),
        )
    } else if zero == s.stamp.len() {
        (
            std::mem::take(&mut s.log_time),
            false,
            format!(
                "{}: the {} is zero, negative or NaN in every message",
                s.log_time_name, s.stamp_name
            ),
        )
    } else {
        (
            std::mem::take(&mut s.log_time),
            false,
            format!(
                "{}: the {} is zero, negative or NaN in {zero} of {} messages, and one clock must time them all",
                s.log_time_name,
                s.stamp_name,
                s.stamp.len()
            ),
        )
    }
}

/// Above this share of the log skipped, a loss says so in its message.
const LOSS_SHARE: f64 = 0.01;

/// Each stretch of the log skipped as a problem with its byte offsets:
/// data dropped is never "problems none".
fn losses(path: &Path, losses: &[crate::streams::Loss], report: &mut ReadReport) {
    let size = std::fs::metadata(path)
        .ok()
        .filter(|m| m.is_file())
        .map(|m| m.len());
    let total: u64 = losses.iter().map(|l| l.bytes).sum();
    let share = size.filter(|&s| s > 0).map(|s| total as f64 / s as f64);
    for (k, l) in losses.iter().enumerate() {
        if k >= imu::read_report::MAX_LISTED {
            report.unlisted += 1;
            continue;
        }
        let of_log = match share {
            Some(f) if k == 0 && f > LOSS_SHARE => format!(
                "; {} stretch{} skipped, {total} bytes in all, {:.1} % of the log",
                losses.len(),
                if losses.len() == 1 { "" } else { "es" },
                100.0 * f
            ),
            _ => String::new(),
        };
        report.problems.push(Problem {
            kind: ProblemKind::SkippedData,
            line: None,
            column: None,
            channel: None,
            count: 1,
            message: format!(
                "bytes {}..{} ({} bytes) skipped: {}{of_log}",
                l.offset,
                l.offset + l.bytes,
                l.bytes,
                l.why
            ),
        });
    }
}

/// Each message skipped as undecodable as a problem; the first also gives
/// the share of the IMU and temperature messages, past [`LOSS_SHARE`].
fn bad_messages(skipped: &[crate::streams::BadMessage], read: usize, report: &mut ReadReport) {
    let bad: usize = skipped.iter().map(|m| m.count).sum();
    let share = bad as f64 / (bad + read).max(1) as f64;
    for (k, m) in skipped.iter().enumerate() {
        if k >= imu::read_report::MAX_LISTED {
            report.unlisted += 1;
            continue;
        }
        let of_log = if k == 0 && share > LOSS_SHARE {
            format!(
                "; {bad} of {} messages skipped, {:.1} %",
                bad + read,
                100.0 * share
            )
        } else {
            String::new()
        };
        report.problems.push(Problem {
            kind: ProblemKind::SkippedData,
            line: None,
            column: None,
            channel: None,
            count: m.count,
            message: format!("{} skipped: {}{of_log}", m.at, m.why),
        });
    }
}

/// What a stream's stamps are, for a clock that cannot be fitted: how many
/// are unusable, repeat the previous one or step back. `t` is taken from
/// its first finite stamp `t0`: a zero or negative stamp is unusable as it
/// was read, the first one too (all-zero stamps are all zeros, not one
/// origin and repeats of it).
fn describe_stamps(t: &[f64], t0: f64) -> String {
    let read: Vec<f64> = t
        .iter()
        .map(|v| v + t0)
        .map(|v| if v > 0.0 { v } else { f64::NAN })
        .collect();
    imu::timing::describe_stamps(&read, "messages", "have a zero, negative or NaN stamp")
}

/// Value of (t, v) at `at`, linear between neighbours; the end values
/// hold for one step of the series beyond its ends, NaN further out.
fn interpolate(t: &[f64], v: &[f64], at: &[f64]) -> Vec<f64> {
    let step = mean_rate(t).map_or(f64::INFINITY, |r| 1.0 / r);
    let mut j = 0;
    at.iter()
        .map(|&x| {
            if t.is_empty() || !x.is_finite() {
                return f64::NAN;
            }
            while j + 1 < t.len() && t[j + 1] <= x {
                j += 1;
            }
            if x < t[0] {
                return if t[0] - x <= step { v[0] } else { f64::NAN };
            }
            if j + 1 >= t.len() {
                return if x - t[j] <= step { v[j] } else { f64::NAN };
            }
            let (t0, t1) = (t[j], t[j + 1]);
            if t1 > t0 {
                v[j] + (v[j + 1] - v[j]) * (x - t0) / (t1 - t0)
            } else {
                v[j]
            }
        })
        .collect()
}

/// One over the median of the positive steps between times, Hz.
fn step_rate(t: &[f64]) -> Option<f64> {
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
    if steps.is_empty() {
        return None;
    }
    let mid = steps.len() / 2;
    let (_, m, _) = steps.select_nth_unstable_by(mid, f64::total_cmp);
    Some(1.0 / *m)
}

/// Every stream of the log, none selected yet; an IMU stream's
/// temperature source as it would be read.
fn summaries(d: &Decoded) -> Vec<StreamInfo> {
    let mut streams: Vec<StreamInfo> = d
        .imu
        .iter()
        .map(|x| StreamInfo {
            name: x.name.clone(),
            kind: "imu",
            instance: x.instance,
            msg_type: x.msg_type.clone(),
            messages: x.len(),
            rate_hz: x.mean_rate_hz(),
            step_rate_hz: step_rate(&x.log_time),
            temperature: if x.temp.is_some() {
                TempSource::Inline(format!("{}.temperature", x.name)).to_string()
            } else {
                match d.temps.as_slice() {
                    [one] => TempSource::Topic(one.name.clone()).to_string(),
                    _ => TempSource::None.to_string(),
                }
            },
            selected: false,
        })
        .collect();
    streams.extend(d.temps.iter().map(|x| StreamInfo {
        name: x.name.clone(),
        kind: "temperature",
        instance: None,
        msg_type: x.msg_type.clone(),
        messages: x.value.len(),
        rate_hz: mean_rate(&x.log_time),
        step_rate_hz: step_rate(&x.log_time),
        temperature: String::new(),
        selected: false,
    }));
    streams
}

/// A recording assembled: the chosen stream on its clock, the report of
/// its clock, and every stream of the log.
pub type Assembled = (Recording, ReadReport, Vec<StreamInfo>);

/// Which IMU stream a choice takes, and its temperature topic, if any.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Plan {
    imu: usize,
    temp_topic: Option<usize>,
}

/// The streams `c` takes from the whole log, before any moves out.
fn plan(path: &Path, d: &Decoded, c: &Choice) -> Result<Plan, LogError> {
    let imu = choose(path, d, c)?;
    let temp_topic = if d.imu[imu].temp.is_some() && c.temp_topic.is_none() {
        None
    } else {
        choose_temp(path, d, c)?.and_then(|t| d.temps.iter().position(|x| x.name == t.name))
    };
    Ok(Plan { imu, temp_topic })
}

/// Builds the recording of the chosen stream, with the report of its clock.
pub fn assemble(path: &Path, format: &str, mut d: Decoded, c: &Choice) -> Result<Assembled, LogError> {
    let plan = plan(path, &d, c)?;
    let streams = summaries(&d);
    build(path, format, &mut d, c, plan, streams, false)
}

/// [`assemble`] of each choice from one decode: every stream is chosen on
/// the whole log first, then each moves out into its recording, so the
/// log's samples are held once (a stream two choices take is copied for
/// the first).
pub fn assemble_each(
    path: &Path,
    format: &str,
    mut d: Decoded,
    choices: &[Choice],
) -> Result<Vec<Assembled>, LogError> {
    let plans: Vec<Plan> = choices
        .iter()
        .map(|c| plan(path, &d, c))
        .collect::<Result<_, _>>()?;
    let streams = summaries(&d);
    let mut out = Vec::with_capacity(choices.len());
    for (k, (c, &p)) in choices.iter().zip(&plans).enumerate() {
        let again = plans[k + 1..].iter().any(|q| q.imu == p.imu);
        out.push(build(path, format, &mut d, c, p, streams.clone(), again)?);
    }
    Ok(out)
}

/// The recording of `plan`'s stream, moved out of `d` (copied where
/// `keep`, for a later choice of the same stream); `streams` are the log's
/// streams as decoded.
fn build(
    path: &Path,
    format: &str,
    d: &mut Decoded,
    c: &Choice,
    plan: Plan,
    mut streams: Vec<StreamInfo>,
    keep: bool,
) -> Result<Assembled, LogError> {
    let Plan { imu: idx, temp_topic } = plan;
    let read_messages: usize = streams.iter().map(|s| s.messages).sum();
    // The chosen stream's samples move into the recording: memory stays
    // near the decoded data, with no second copy of the stream.
    let mut s = if keep {
        d.imu[idx].clone()
    } else {
        std::mem::take(&mut d.imu[idx])
    };
    let messages = s.len();
    let (mut t, stamped, why) = time_source(&mut s);
    s.stamp = Vec::new();
    s.log_time = Vec::new();
    let t0 = t.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0);
    t.iter_mut().for_each(|v| *v -= t0);

    let mut report = ReadReport {
        rows: messages,
        lines: messages as u64,
        ..ReadReport::default()
    };
    report.notes.extend(d.notes.iter().cloned());
    losses(path, &d.losses, &mut report);
    bad_messages(&d.bad_messages, read_messages, &mut report);
    report.notes.push(format!("time source: {why}"));

    let (temp, temp_source) = match (temp_topic.map(|k| &d.temps[k]), s.temp.take()) {
        (Some(tt), _) => {
            let use_stamp = stamped && tt.stamp.iter().all(|v| v.is_finite());
            let tt_t = if use_stamp { &tt.stamp } else { &tt.log_time };
            let tt_rel: Vec<f64> = tt_t.iter().map(|v| v - t0).collect();
            (
                Some(interpolate(&tt_rel, &tt.value, &t)),
                TempSource::Topic(tt.name.clone()),
            )
        }
        (None, Some(inline)) => (
            Some(inline),
            TempSource::Inline(format!("{}.temperature", s.name)),
        ),
        (None, None) => (None, TempSource::None),
    };

    let has_temp = temp.is_some();
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(7);
    columns.extend(std::mem::take(&mut s.accel));
    columns.extend(std::mem::take(&mut s.gyro));
    columns.extend(temp);
    let mut timing = analyze_timestamps(&t);
    if timing.is_none() && messages > 1 {
        // No two stamps step forward: nothing to fit a clock to. Without
        // a rate this is refused, never a silent 1 Hz; with one, the
        // samples take its period in the order of the log, said loudly.
        let detail = describe_stamps(&t, t0);
        let Some(r) = c.rate_hz else {
            return Err(LogError::new(
                path,
                LogErrorKind::NoClock {
                    stream: s.name.clone(),
                    detail,
                },
            ));
        };
        report.notes.push(format!(
            "the stamps of {} cannot time it ({detail}): its {messages} samples are placed one per 1/{r} s ({}) in the order of the log",
            s.name,
            Setting::SampleRate.given(Value::number(r))
        ));
        t = (0..messages).map(|k| k as f64 / r).collect();
        timing = analyze_timestamps(&t);
    }
    for (k, _) in t.iter().enumerate().filter(|(_, v)| !v.is_finite()) {
        if report.problems.len() >= imu::read_report::MAX_LISTED {
            report.unlisted += 1;
            continue;
        }
        report.problems.push(Problem {
            kind: ProblemKind::NoStamp,
            line: None,
            column: None,
            channel: None,
            count: 1,
            message: format!("message {} has no usable stamp (zero, negative or NaN)", k + 1),
        });
    }
    let rate = c.rate_hz.or(timing.as_ref().map(|tm| tm.rate_hz));
    // On its own clock without a gap or a repeated stamp, every message
    // already sits in its slot: the grid is the columns as they are.
    let in_place = c.rate_hz.is_none()
        && timing
            .as_ref()
            .is_some_and(|tm| tm.gaps.is_empty() && tm.duplicates.is_empty());
    let (grid, dropped) = match rate {
        Some(_) if in_place => (columns, Vec::new()),
        Some(r) => {
            let factor = timing
                .as_ref()
                .map_or(c.max_grid_factor.unwrap_or(imu::timing::MAX_GRID_FACTOR), |tm| {
                    tm.grid_factor(c.max_grid_factor, r)
                });
            let gap_above = timing
                .as_ref()
                .map_or(imu::timing::GAP_FACTOR / r, |tm| tm.gap_above_for(r));
            regularize_gapped(&t, r, gap_above, &columns, factor).ok_or_else(|| {
                let own = timing.as_ref().map(|tm| tm.rate_hz);
                LogError::new(path, bad_clock(&s.name, &t, c.rate_hz, own, factor))
            })?
        }
        None => (columns, Vec::new()),
    };
    if let Some(tm) = &timing {
        let slots = grid.first().map_or(0, Vec::len);
        report.notes.extend(tm.pattern_note(messages, slots));
    }
    if let Some(tm) = &timing {
        let mut since = 0usize;
        for &(row, missing) in &tm.gaps {
            since += 1;
            if since > imu::read_report::MAX_LISTED {
                report.unlisted += 1;
                continue;
            }
            report.problems.push(Problem {
                kind: ProblemKind::TimeGap,
                line: None,
                column: None,
                channel: None,
                count: missing,
                message: gap_message(missing, row, &t),
            });
        }
        for (kind, rows, what) in [
            (
                ProblemKind::DuplicateTime,
                &tm.duplicates,
                "repeats the previous stamp; kept in the next slot",
            ),
            (
                ProblemKind::BackwardsTime,
                &tm.backwards,
                "is stamped before the previous one; kept in the next slot",
            ),
        ] {
            for &row in rows.iter() {
                if report.problems.len() >= imu::read_report::MAX_LISTED {
                    report.unlisted += 1;
                    continue;
                }
                report.problems.push(Problem {
                    kind,
                    line: None,
                    column: None,
                    channel: None,
                    count: 1,
                    message: format!("message {} (t = {:.6} s) {what}", row + 1, t[row]),
                });
            }
        }
        report.dropped_samples = dropped.len();
    }
    report.timing = timing;

    let mut grid = grid.into_iter();
    let mut channels = Vec::with_capacity(7);
    let ros = [
        [
            "linear_acceleration.x",
            "linear_acceleration.y",
            "linear_acceleration.z",
        ],
        ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"],
    ];
    let fields = s.axis_fields.unwrap_or(ros);
    for (q, names) in [Quantity::Acceleration, Quantity::AngularRate]
        .into_iter()
        .zip(fields)
    {
        for (axis, field) in Axis::ALL.into_iter().zip(names) {
            let mut ch = Channel::inertial(q, axis, grid.next().unwrap_or_default());
            ch.source_name = format!("{}.{field}", s.name);
            channels.push(ch);
        }
    }
    if has_temp {
        let mut ch = Channel::temperature(grid.next().unwrap_or_default());
        ch.source_name = temp_source.to_string();
        channels.push(ch);
    }

    let mut rec = Recording {
        channels,
        rate_hz: rate,
        timestamps: Some(t),
        ..Recording::default()
    };
    rec.meta.source = Some(path.to_path_buf());
    rec.meta.entries.extend(d.entries.iter().cloned());
    rec.meta.set("log_format", format);
    rec.meta.set("stream", &s.name);
    rec.meta.set("message_type", &s.msg_type);
    if let Some(i) = s.instance {
        rec.meta.set("instance", i.to_string());
    }
    if let Some(id) = s.device_id {
        rec.meta.set("device_id", id.to_string());
    }
    if let Some(f) = s.frame_id.as_ref().filter(|f| !f.is_empty()) {
        rec.meta.set("frame_id", f);
    }
    rec.meta.set(
        "time_source",
        if stamped { s.stamp_name } else { s.log_time_name },
    );
    rec.meta.set("time_source_reason", why);
    rec.meta.set("temperature_source", temp_source.to_string());
    rec.meta.device = Some(match s.device_id {
        Some(id) => format!("{format} {} (device id {id})", s.name),
        None => format!("{format} {}", s.name),
    });

    for x in &mut streams {
        if x.kind == "imu" && x.name == s.name {
            x.temperature = temp_source.to_string();
            x.selected = true;
        }
        if x.kind == "temperature" {
            x.selected = matches!(&temp_source, TempSource::Topic(n) if *n == x.name);
        }
    }
    Ok((rec, report, streams))
}

/// Why stamps `t` (s) of stream `name` could not be placed on a grid of
/// at most `factor` slots a sample: a rate given for them is blamed where
/// the stamps' own rate `own` would have placed them, else the stamps are.
fn bad_clock(name: &str, t: &[f64], given: Option<f64>, own: Option<f64>, factor: usize) -> LogErrorKind {
    let span_s = match (t.first(), t.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    let stamps_hold = own.is_some_and(|r| r * span_s <= (factor * t.len()) as f64);
    match given {
        Some(rate) if stamps_hold && span_s > 0.0 => LogErrorKind::RateTooHigh(Box::new(RateTooHigh {
            stream: name.to_string(),
            given: Setting::SampleRate.given(Value::number(rate)),
            span_s,
            slots: span_s * rate,
            samples: t.len(),
        })),
        _ => LogErrorKind::BadClock(name.to_string()),
    }
}

/// The problem line of `missing` samples lost before message `row` (from
/// 0) of a stream stamped `t` (s from its first message). A gap right
/// after the first message is the start of the log: the stream's first
/// stretch is one message, then nothing, which a cut or a late logger
/// leaves, and no earlier message stands before it to name.
fn gap_message(missing: usize, row: usize, t: &[f64]) -> String {
    let samples = format!("{missing} sample{}", if missing == 1 { "" } else { "s" });
    if row == 1 {
        return format!(
            "{samples} missing at the start of the stream: its first message, then none for {:.6} s \
             (message 2 at t = {:.6} s)",
            t[1] - t[0],
            t[1]
        );
    }
    format!(
        "{samples} missing before message {} (t = {:.6} s, after {:.6} s without a sample)",
        row + 1,
        t[row],
        t[row] - t[row - 1]
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_gap_after_the_first_message_is_the_start_of_the_stream() {
        let t = [0.0, 0.161303, 0.166303, 0.2];
        let start = gap_message(32, 1, &t);
        assert_eq!(
            start,
            "32 samples missing at the start of the stream: its first message, then none for 0.161303 s \
             (message 2 at t = 0.161303 s)"
        );
        let later = gap_message(1, 3, &t);
        assert!(
            later.starts_with("1 sample missing before message 4 (t = 0.200000 s"),
            "{later}"
        );
    }

    use super::*;

    /// A log of one stream whose stamps and log times are `t`.
    fn log_of(t: &[f64]) -> Decoded {
        let mut d = Decoded::default();
        let s = d.imu_mut("imu", "sensor_msgs/msg/Imu");
        s.stamp_name = "header.stamp";
        s.log_time_name = "bag time";
        for (k, &v) in t.iter().enumerate() {
            s.push(v, v, [k as f64; 3], [0.0; 3], None);
        }
        d
    }

    /// A stream logged at 50 Hz for 2 s, silent for 36 s, then 2 s again:
    /// its messages average 5 Hz over the span, but flow at 50 Hz, the rate
    /// its clock reads.
    #[test]
    fn a_stream_with_gaps_gives_its_rate_between_messages_beside_its_mean() {
        let t: Vec<f64> = (0..100)
            .map(|k| k as f64 * 0.02)
            .chain((0..101).map(|k| 38.0 + k as f64 * 0.02))
            .collect();
        let s = &summaries(&log_of(&t))[0];
        assert!((s.rate_hz.unwrap() - 200.0 / 40.0).abs() < 1e-9, "{s:?}");
        assert!((s.step_rate_hz.unwrap() - 50.0).abs() < 1e-6, "{s:?}");
        assert_eq!(step_rate(&[1.0]), None);
        assert_eq!(step_rate(&[1.0, 1.0]), None);
    }

    #[test]
    fn a_rate_the_stamps_cannot_hold_is_blamed_not_the_stamps() {
        let t: Vec<f64> = (0..50).map(|k| k as f64 * 0.01).collect();
        let absurd = Choice {
            rate_hz: Some(1e12),
            ..Choice::default()
        };
        let e = assemble(Path::new("x.mcap"), "MCAP", log_of(&t), &absurd).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(&e.kind, LogErrorKind::RateTooHigh(r) if r.samples == 50),
            "{text}"
        );
        assert!(
            text.contains("the sample rate given") && text.contains("4.900e11 periods"),
            "{text}"
        );
        // Stamps that no rate places are still the stamps' fault.
        let spread = [0.0, 0.01, 0.02, 0.03, 1000.0];
        let rated = Choice {
            rate_hz: Some(100.0),
            ..Choice::default()
        };
        let e = assemble(Path::new("x.mcap"), "MCAP", log_of(&spread), &rated).unwrap_err();
        assert!(matches!(e.kind, LogErrorKind::BadClock(_)), "{e}");
    }

    #[test]
    fn stamps_without_a_clock_are_refused_unless_a_rate_is_given() {
        for (t, says) in [
            (vec![0.0; 5], "5 have a zero, negative or NaN stamp, 0 repeat"),
            (vec![f64::NAN; 5], "5 have a zero, negative or NaN stamp"),
            (
                vec![4.0, 3.0, 2.0, 1.0, 0.0],
                "1 have a zero, negative or NaN stamp, 0 repeat the previous stamp and 3 step back",
            ),
        ] {
            let e = assemble(Path::new("x.bag"), "ROS 1 bag", log_of(&t), &Choice::default()).unwrap_err();
            let text = e.to_string();
            assert!(matches!(e.kind, LogErrorKind::NoClock { .. }), "{text}");
            assert!(
                text.contains(says) && text.contains("the sample rate HZ"),
                "{text}"
            );
            let rated = Choice {
                rate_hz: Some(100.0),
                ..Choice::default()
            };
            let (rec, report, _) = assemble(Path::new("x.bag"), "ROS 1 bag", log_of(&t), &rated).unwrap();
            assert_eq!(rec.rate_hz, Some(100.0));
            assert!(
                report
                    .notes
                    .iter()
                    .any(|n| n.contains("cannot time it") && n.contains("(the sample rate 100)")),
                "{:?}",
                report.notes
            );
        }
    }

    #[test]
    fn a_message_without_a_stamp_is_a_problem_with_its_number() {
        let mut t: Vec<f64> = (0..50).map(|k| k as f64 * 0.01).collect();
        t[7] = f64::NAN;
        let (_, report, _) =
            assemble(Path::new("x.bag"), "ROS 1 bag", log_of(&t), &Choice::default()).unwrap();
        let p: Vec<&Problem> = report
            .problems
            .iter()
            .filter(|p| p.kind == ProblemKind::NoStamp)
            .collect();
        assert_eq!(p.len(), 1, "{:?}", report.problems);
        assert!(p[0].message.contains("message 8 "), "{}", p[0].message);
    }

    #[test]
    fn temperature_is_interpolated_and_not_extended_past_a_step() {
        let t = [0.0, 1.0, 2.0];
        let v = [10.0, 20.0, 30.0];
        let got = interpolate(&t, &v, &[-0.5, 0.0, 0.25, 1.5, 2.0, 2.9, 3.5, -2.0]);
        assert_eq!(&got[..6], &[10.0, 10.0, 12.5, 25.0, 30.0, 30.0]);
        assert!(got[6].is_nan() && got[7].is_nan());
    }
}
