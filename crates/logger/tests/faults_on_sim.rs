//! One fault at a time, in simulated time: what the recorder writes and
//! how the run ends.

use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::sim::FaultSchedule;

mod support;
use support::{Run, counter_index, rows, trailer};

#[test]
fn a_brown_out_is_reconfigured_and_its_silence_is_a_gap() {
    // The chip loses its registers 2 s in: nothing comes until the recorder
    // notices (1 s without a frame) and configures it again.
    let config = Config::default();
    let run = Run {
        config,
        seconds: Some(5.0),
        faults: FaultSchedule {
            brownout_at_s: Some(2.0),
            ..FaultSchedule::default()
        },
        ..Run::default()
    }
    .record();
    let text = &run.text;
    assert_eq!(trailer(text, "reconfigurations"), 1.0, "{text}");
    assert_eq!(trailer(text, "gaps"), 1.0);
    assert!(text.contains("the sensor stopped delivering: reconfigured"));
    let r = rows(text);
    assert_eq!(r.len(), 1000);
    let gap = r.iter().filter(|row| row[0].is_nan()).count();
    // About a second of silence and the poll that notices it.
    assert!((195..=240).contains(&gap), "{gap} gap rows");
    // Across the gap the stream resumes where the chip's time says: the
    // rows lost number the samples the chip's clock passed, to ±1.
    let first_after = r.iter().position(|row| row[0].is_nan()).unwrap() + gap;
    let before = counter_index(&r[first_after - gap - 1], &config).unwrap();
    let after = counter_index(&r[first_after], &config).unwrap();
    assert!(
        ((after - before - 1) - gap as i64).abs() <= 1,
        "{before} → {after} over {gap} rows"
    );
}

#[test]
fn a_silent_chip_ends_the_run_at_the_duration_in_host_time() {
    // A chip whose clock has stopped never delivers: the run still ends,
    // at 1.05 × the duration + 2 s, the silence written as a gap.
    let run = Run {
        config: Config {
            rate_hz: 100.0,
            ..Config::default()
        },
        seconds: Some(1.0),
        faults: FaultSchedule {
            clock_ppm: -1_000_000.0,
            ..FaultSchedule::default()
        },
        ..Run::default()
    }
    .record();
    assert!(run.text.contains("stopped_by=time_limit"), "{}", run.text);
    assert_eq!(trailer(&run.text, "samples"), 0.0);
    assert_eq!(rows(&run.text).len(), 100, "the whole second is a gap");
    assert!((3.05..3.2).contains(&run.host_s), "{} s", run.host_s);
}

#[test]
fn a_stop_request_still_writes_what_the_fifo_holds_and_a_complete_file() {
    let config = Config {
        rate_hz: 500.0,
        ..Config::default()
    };
    let run = Run {
        config,
        stop_at: Some(2.5),
        ..Run::default()
    }
    .record();
    let text = &run.text;
    assert!(text.ends_with('\n'));
    assert!(text.contains("stopped_by=signal"), "{text}");
    let r = rows(text);
    // Every sample the chip made up to the last read, in order: from the
    // end of the configuration (0.1 s of start-up after its reset) to the
    // read after 2.5 s.
    assert!((1195..=1215).contains(&r.len()), "{} rows", r.len());
    let ks: Vec<i64> = r.iter().map(|row| counter_index(row, &config).unwrap()).collect();
    assert!(ks.windows(2).all(|w| w[1] == w[0] + 1));
}

#[test]
fn a_sensor_gone_for_good_ends_the_run_with_an_error_and_a_trailer() {
    // Every transfer fails: after 30 s without a frame the run gives up,
    // the silence written as a gap and the file closed as always.
    let run = Run {
        faults: FaultSchedule {
            bus_errors: 1.0,
            ..FaultSchedule::default()
        },
        ..Run::default()
    }
    .record();
    let err = run.summary.unwrap_err();
    assert!(err.contains("no sample from the sensor for 30 s"), "{err}");
    assert!(run.text.contains("stopped_by=error"), "{}", run.text);
    let gap = trailer(&run.text, "gap_samples");
    // 30 s at 200 Hz, and the poll that notices it.
    assert!((6000.0..=6010.0).contains(&gap), "{gap}");
    assert!(trailer(&run.text, "bus_errors") > 1000.0);
}

#[test]
fn full_scale_sets_the_quantization_step() {
    let config = Config {
        rate_hz: 100.0,
        gyro_range: GyroRange::Dps2000,
        accel_range: AccelRange::G16,
        ..Config::default()
    };
    let run = Run {
        config,
        seconds: Some(1.0),
        source: Some(Box::new(|k, _| {
            let x = (k as f64 * 0.37).sin();
            [x, 2.0 * x, 9.8, 0.1 * x, -0.2 * x, 0.3, 25.0]
        })),
        ..Run::default()
    }
    .record();
    let (g, a) = (std::f64::consts::PI / 180.0 / 16.4, 9.80665 / 2048.0);
    let r = rows(&run.text);
    assert_eq!(r.len(), 100);
    for row in r {
        let (kg, ka) = (row[3] / g, row[0] / a);
        assert!(
            (kg - kg.round()).abs() < 1e-6 && (ka - ka.round()).abs() < 1e-6,
            "{row:?}"
        );
    }
}
