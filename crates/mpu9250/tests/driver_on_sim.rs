//! The driver against the register-level simulated chip.

use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{Chip, Error, FifoRead, I2cBus, Mpu9250, SpiBus};
use mpu9250::sim::{ADDRESS, SimChip};

/// Sample k reads k LSB on every axis and on the temperature: a frame whose
/// seven fields differ was decoded from misaligned bytes.
fn counting(cfg: Config) -> SimChip {
    let (a, g) = (cfg.accel_range.lsb_si(), cfg.gyro_range.lsb_rad());
    SimChip::new(Box::new(move |k, _| {
        let v = (k % 30_000) as f64;
        [v * a, v * a, v * a, v * g, v * g, v * g, v / 333.87 + 21.0]
    }))
}

#[test]
fn probes_the_family_and_refuses_strangers() {
    let imu = Mpu9250::new(I2cBus::new(SimChip::new(Box::new(|_, _| [0.0; 7])), ADDRESS)).unwrap();
    assert_eq!(imu.chip(), Chip::Mpu9250);
    let imu = Mpu9250::new(I2cBus::new(
        SimChip::new(Box::new(|_, _| [0.0; 7])).with_who_am_i(0x73),
        ADDRESS,
    ))
    .unwrap();
    assert_eq!(imu.chip(), Chip::Mpu9255);
    let e = Mpu9250::new(I2cBus::new(
        SimChip::new(Box::new(|_, _| [0.0; 7])).with_who_am_i(0x12),
        ADDRESS,
    ))
    .unwrap_err();
    assert!(matches!(e, Error::UnknownDevice(0x12)), "{e}");
    // Nobody at 0x69.
    assert!(matches!(
        Mpu9250::new(I2cBus::new(SimChip::new(Box::new(|_, _| [0.0; 7])), 0x69)),
        Err(Error::Bus(_))
    ));
}

#[test]
fn ten_seconds_at_200_hz_are_2000_aligned_frames() {
    let cfg = Config::default();
    let mut imu = Mpu9250::new(I2cBus::new(counting(cfg), ADDRESS)).unwrap();
    imu.configure(cfg).unwrap();
    let mut frames = Vec::new();
    for _ in 0..200 {
        imu.bus_mut().inner_mut().advance(0.05);
        assert!(matches!(imu.read_fifo(&mut frames).unwrap(), FifoRead::Frames(_)));
    }
    assert_eq!(frames.len(), 2000);
    for (k, f) in frames.iter().enumerate() {
        assert!(f.iter().all(|&v| v == k as i16), "frame {k}: {f:?}");
    }
}

#[test]
fn full_scale_sets_the_quantization_step() {
    for (g, a) in [
        (GyroRange::Dps250, AccelRange::G2),
        (GyroRange::Dps2000, AccelRange::G16),
    ] {
        let cfg = Config {
            gyro_range: g,
            accel_range: a,
            ..Config::default()
        };
        // A slow ramp, far from any LSB multiple.
        let chip = SimChip::new(Box::new(|k, _| {
            let v = 1e-3 * k as f64 + 1e-4;
            [v, v, v, v * 0.01, v * 0.01, v * 0.01, 25.0]
        }));
        let mut imu = Mpu9250::new(I2cBus::new(chip, ADDRESS)).unwrap();
        imu.configure(cfg).unwrap();
        imu.bus_mut().inner_mut().advance(0.1);
        let mut frames = Vec::new();
        imu.read_fifo(&mut frames).unwrap();
        for f in &frames {
            let si = cfg.to_si(f);
            let (ka, kg) = (si[0] / a.lsb_si(), si[3] / g.lsb_rad());
            assert!((ka - ka.round()).abs() < 1e-9 && (kg - kg.round()).abs() < 1e-9);
        }
        // The datasheet's LSBs: 16384 LSB/g at ±2 g, 16.4 LSB/(°/s) at ±2000 °/s.
        assert!((AccelRange::G2.lsb_si() - 9.80665 / 16384.0).abs() < 1e-15);
        assert!((GyroRange::Dps2000.lsb_per_dps() - 16.4).abs() < 1e-12);
    }
}

#[test]
fn an_overflow_is_reported_and_the_stream_resumes_aligned() {
    let cfg = Config::default();
    let mut imu = Mpu9250::new(I2cBus::new(counting(cfg), ADDRESS)).unwrap();
    imu.configure(cfg).unwrap();
    let mut frames = Vec::new();
    imu.bus_mut().inner_mut().advance(0.05);
    imu.read_fifo(&mut frames).unwrap();
    // A slow reader: one second unread at 200 Hz is 2800 bytes for a 512-byte FIFO.
    imu.bus_mut().inner_mut().advance(1.0);
    assert_eq!(imu.read_fifo(&mut frames).unwrap(), FifoRead::Overflow);
    let before = frames.len();
    for _ in 0..10 {
        imu.bus_mut().inner_mut().advance(0.05);
        imu.read_fifo(&mut frames).unwrap();
    }
    assert!(frames.len() - before >= 99);
    // Every frame whole (its seven fields equal), consecutive after the gap.
    for f in &frames {
        assert!(f.iter().all(|&v| v == f[0]), "misaligned frame {f:?}");
    }
    let after: Vec<i16> = frames[before..].iter().map(|f| f[0]).collect();
    assert!(after.windows(2).all(|w| w[1] == w[0] + 1));
    assert!(after[0] > frames[before - 1][0] + 1, "the gap is there");
    assert_eq!(imu.bus_mut().inner_mut().stats().overflows, 1);
}

#[test]
fn injected_bus_errors_are_errors_and_retries_lose_nothing() {
    let cfg = Config::default();
    let mut imu = loop {
        // Probing and configuring may meet an injected error too: retry.
        let Ok(mut imu) = Mpu9250::new(I2cBus::new(counting(cfg).with_error_rate(0.01), ADDRESS)) else {
            continue;
        };
        if imu.configure(cfg).is_ok() {
            break imu;
        }
    };
    let mut frames = Vec::new();
    let mut errors = 0;
    for _ in 0..400 {
        imu.bus_mut().inner_mut().advance(0.025);
        loop {
            match imu.read_fifo(&mut frames) {
                Ok(_) => break,
                Err(Error::Bus(_)) => errors += 1,
                Err(e) => panic!("{e}"),
            }
        }
    }
    assert!(errors > 0, "1 % of a few thousand transfers");
    assert_eq!(frames.len(), 2000);
    assert!(frames.iter().enumerate().all(|(k, f)| f[0] == k as i16));
    // Every error the chip injected after configuration surfaced as one.
    assert!(imu.bus_mut().inner_mut().stats().injected_errors as usize >= errors);
}

#[test]
fn spi_reads_the_same_chip() {
    let cfg = Config::default();
    let mut imu = Mpu9250::new(SpiBus::new(counting(cfg))).unwrap();
    imu.configure(cfg).unwrap();
    imu.bus_mut().inner_mut().advance(0.1);
    let mut frames = Vec::new();
    assert_eq!(imu.read_fifo(&mut frames).unwrap(), FifoRead::Frames(20));
    assert!(
        frames
            .iter()
            .enumerate()
            .all(|(k, f)| f.iter().all(|&v| v == k as i16))
    );
}
