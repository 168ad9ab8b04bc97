//! The driver against the register-level simulated chip.

use embedded_hal::delay::DelayNs;
use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{Bus, Chip, Error, FifoRead, I2cBus, Mpu9250, SpiBus};
use mpu9250::frame::RawFrame;
use mpu9250::regs;
use mpu9250::sim::{ADDRESS, SimChip, SimDelay, SimError, SimStats, imu_on_i2c, imu_on_spi};

/// Every whole frame in the FIFO appended to `out` as its seven words in
/// register order: these tests compare words, where the driver names the
/// fields.
fn read_words<B: Bus, D: DelayNs>(
    imu: &mut Mpu9250<B, D>,
    out: &mut Vec<[i16; 7]>,
) -> Result<FifoRead, Error<B::Error>> {
    let mut frames = Vec::new();
    let read = imu.read_frames(&mut frames);
    out.extend(frames.into_iter().map(<[i16; 7]>::from));
    read
}

/// The driver on I2C, configured with `cfg`, over a [`counting`] chip.
fn configured(cfg: Config) -> Mpu9250<I2cBus<SimChip>, SimDelay> {
    let mut imu = imu_on_i2c(counting(cfg), ADDRESS).unwrap();
    imu.configure(cfg).unwrap();
    imu
}

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
    let imu = imu_on_i2c(SimChip::new(Box::new(|_, _| [0.0; 7])), ADDRESS).unwrap();
    assert_eq!(imu.chip(), Chip::Mpu9250);
    let imu = imu_on_i2c(
        SimChip::new(Box::new(|_, _| [0.0; 7])).with_who_am_i(0x73),
        ADDRESS,
    )
    .unwrap();
    assert_eq!(imu.chip(), Chip::Mpu9255);
    let e = imu_on_i2c(
        SimChip::new(Box::new(|_, _| [0.0; 7])).with_who_am_i(0x12),
        ADDRESS,
    )
    .unwrap_err();
    assert!(matches!(e, Error::UnknownDevice(0x12)), "{e}");
    // Nobody at 0x69.
    assert!(matches!(
        imu_on_i2c(SimChip::new(Box::new(|_, _| [0.0; 7])), 0x69),
        Err(Error::Bus(_))
    ));
}

#[test]
fn ten_seconds_at_200_hz_are_2000_aligned_frames() {
    let cfg = Config::default();
    let mut imu = configured(cfg);
    let mut frames = Vec::new();
    for _ in 0..200 {
        imu.bus_mut().inner_mut().advance(0.05);
        assert!(matches!(
            read_words(&mut imu, &mut frames).unwrap(),
            FifoRead::Frames(_)
        ));
    }
    assert_eq!(frames.len(), 2000);
    for (k, f) in frames.iter().enumerate() {
        assert!(f.iter().all(|&v| v == k as i16), "frame {k}: {f:?}");
    }
}

/// The named frames are the register-order words, field by field: the
/// temperature is the fourth word and the gyroscope follows it.
#[test]
fn named_frames_hold_the_same_words_as_register_order_frames() {
    let cfg = Config::default();
    // Each field its own value: a field read from the wrong word shows.
    let chip = |cfg: Config| {
        let (a, g) = (cfg.accel_range.lsb_si(), cfg.gyro_range.lsb_rad());
        SimChip::new(Box::new(move |_, _| {
            [
                a,
                2.0 * a,
                3.0 * a,
                5.0 * g,
                6.0 * g,
                7.0 * g,
                4.0 / 333.87 + 21.0,
            ]
        }))
    };
    let mut growing = imu_on_i2c(chip(cfg), ADDRESS).unwrap();
    let mut fixed = imu_on_i2c(chip(cfg), ADDRESS).unwrap();
    growing.configure(cfg).unwrap();
    fixed.configure(cfg).unwrap();
    growing.bus_mut().inner_mut().advance(0.05);
    fixed.bus_mut().inner_mut().advance(0.05);
    let mut n = Vec::new();
    assert_eq!(growing.read_frames(&mut n).unwrap(), FifoRead::Frames(10));
    // The allocation-free read into a slice that holds the whole FIFO.
    let mut slots = [RawFrame::default(); regs::FIFO_FRAMES];
    assert_eq!(fixed.read_frames_into(&mut slots).unwrap(), FifoRead::Frames(10));
    assert_eq!(&slots[..10], &n[..]);
    for n in &n {
        assert_eq!(<[i16; 7]>::from(*n), [1, 2, 3, 4, 5, 6, 7]);
        assert_eq!((n.accel, n.temp, n.gyro), ([1, 2, 3], 4, [5, 6, 7]));
        let s = cfg.sample(n);
        assert_eq!(
            s.to_log_row()[..6],
            [1.0, 2.0, 3.0, 5.0, 6.0, 7.0].map(|k| k * if k < 4.0 {
                cfg.accel_range.lsb_si()
            } else {
                cfg.gyro_range.lsb_rad()
            })
        );
        assert!((s.temp_c - (4.0 / 333.87 + 21.0)).abs() < 1e-12);
    }
}

/// A slice with room for fewer frames than the FIFO holds takes that many;
/// the rest wait in the FIFO, and the next read brings them, in order.
#[test]
fn a_short_slice_leaves_the_other_frames_in_the_fifo() {
    let mut imu = configured(Config::default());
    imu.bus_mut().inner_mut().advance(0.05); // 10 frames at 200 Hz
    let mut slots = [RawFrame::default(); 4];
    let mut seen = Vec::new();
    for want in [4, 4, 2, 0] {
        assert_eq!(imu.read_frames_into(&mut slots).unwrap(), FifoRead::Frames(want));
        seen.extend(slots[..want].iter().map(|f| f.temp));
    }
    assert_eq!(seen, (0..10).collect::<Vec<i16>>());
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
        let mut imu = imu_on_i2c(chip, ADDRESS).unwrap();
        imu.configure(cfg).unwrap();
        imu.bus_mut().inner_mut().advance(0.1);
        let mut frames = Vec::new();
        read_words(&mut imu, &mut frames).unwrap();
        for f in &frames {
            let si = cfg.sample(&RawFrame::from(*f)).to_log_row();
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
    let mut imu = configured(cfg);
    let mut frames = Vec::new();
    imu.bus_mut().inner_mut().advance(0.05);
    read_words(&mut imu, &mut frames).unwrap();
    // A slow reader: one second unread at 200 Hz is 2800 bytes for a 512-byte FIFO.
    imu.bus_mut().inner_mut().advance(1.0);
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Overflow);
    let before = frames.len();
    for _ in 0..10 {
        imu.bus_mut().inner_mut().advance(0.05);
        read_words(&mut imu, &mut frames).unwrap();
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

/// Reads 2000 samples at 200 Hz through a bus failing 1 % of transfers,
/// retrying every error, and checks that every frame is whole and that the
/// stream jumps only where the driver reported a resynchronisation.
fn read_through_faults<B: mpu9250::driver::Bus>(
    mut imu: Mpu9250<B, SimDelay>,
    chip: fn(&mut Mpu9250<B, SimDelay>) -> &mut SimChip,
) -> (usize, usize) {
    let mut frames: Vec<[i16; 7]> = Vec::new();
    let (mut errors, mut resyncs) = (0, 0);
    let mut jumps_allowed_at = Vec::new();
    for _ in 0..400 {
        chip(&mut imu).advance(0.025);
        loop {
            match read_words(&mut imu, &mut frames) {
                Ok(FifoRead::Frames(_)) => break,
                Ok(FifoRead::Resync) => {
                    resyncs += 1;
                    jumps_allowed_at.push(frames.len());
                }
                Ok(FifoRead::Overflow) => panic!("no overflow at 40 reads a second"),
                Ok(FifoRead::Reconfigured) => panic!("no brown-out here"),
                Err(Error::Bus(_)) => errors += 1,
                Err(e) => panic!("{e}"),
            }
        }
    }
    assert!(errors > 0, "1 % of a few thousand transfers");
    for f in &frames {
        assert!(f.iter().all(|&v| v == f[0]), "misaligned frame {f:?}");
    }
    for (i, w) in frames.windows(2).enumerate() {
        if w[1][0] != w[0][0] + 1 {
            assert!(
                jumps_allowed_at.contains(&(i + 1)),
                "samples {}..{} lost without a resync",
                w[0][0] + 1,
                w[1][0]
            );
        }
    }
    let stats = chip(&mut imu).stats();
    // Each short read of the FIFO cost one resync, and so may a lost reply
    // to the status read that vouches for a burst; address NACKs cost none.
    assert!(
        stats.short_reads <= resyncs as u64 && resyncs as u64 <= stats.short_reads + stats.lost_status_reads,
        "{resyncs} resyncs; {stats:?}"
    );
    // Every sample produced was read, or lost in a resync, or still waits.
    let lost: u64 = frames
        .windows(2)
        .map(|w| (w[1][0] - w[0][0] - 1) as u64)
        .sum::<u64>()
        + frames[0][0] as u64;
    assert!(lost + frames.len() as u64 <= stats.samples);
    (errors, resyncs)
}

#[test]
fn injected_bus_errors_are_retried_and_part_reads_resynchronise() {
    let cfg = Config::default();
    let imu = loop {
        // Probing and configuring may meet an injected error too: retry.
        let Ok(mut imu) = imu_on_i2c(counting(cfg).with_error_rate(0.01), ADDRESS) else {
            continue;
        };
        if imu.configure(cfg).is_ok() {
            break imu;
        }
    };
    let (errors, _) = read_through_faults(imu, |imu| imu.bus_mut().inner_mut());
    assert!(errors > 5);
}

#[test]
fn a_nack_loses_nothing_but_a_part_read_costs_a_resync() {
    let cfg = Config::default();
    let mut imu = configured(cfg);
    let mut frames = Vec::new();
    fn chip(imu: &mut Mpu9250<I2cBus<SimChip>, SimDelay>) -> &mut SimChip {
        imu.bus_mut().inner_mut()
    }
    // An address NACK on the data read: nothing left the FIFO, so the
    // retry reads on as if nothing happened.
    chip(&mut imu).advance(0.1);
    chip(&mut imu).fail_next_fifo_read(SimError::Nack);
    assert!(read_words(&mut imu, &mut frames).is_err());
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(20));
    assert!(frames.iter().enumerate().all(|(k, f)| *f == [k as i16; 7]));
    // A read broken off after 30 bytes (two frames and two bytes).
    chip(&mut imu).advance(0.1);
    chip(&mut imu).fail_next_fifo_read(SimError::ShortRead(30));
    assert!(read_words(&mut imu, &mut frames).is_err());
    // The FIFO is part-read: the driver resets it rather than decode it.
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Resync);
    assert_eq!(chip(&mut imu).fifo_len(), 0);
    chip(&mut imu).advance(0.05);
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(10));
    // Samples 20..40 were lost with the FIFO; the stream resumes at 40.
    assert_eq!(frames.len(), 30);
    assert_eq!(frames[20], [40; 7]);
}

/// The simulated chip on I2C, with the `fail`-th transfer from now (1 =
/// the next) failing before it reaches the chip.
struct FailNth {
    bus: I2cBus<SimChip>,
    fail: u32,
}

impl FailNth {
    fn tick(&mut self) -> Result<(), ()> {
        match self.fail {
            0 => Ok(()),
            1 => {
                self.fail = 0;
                Err(())
            }
            _ => {
                self.fail -= 1;
                Ok(())
            }
        }
    }
}

impl mpu9250::driver::Bus for FailNth {
    type Error = ();
    fn nothing_transferred(_: &()) -> bool {
        true
    }
    fn write_reg(&mut self, reg: u8, value: u8) -> Result<(), ()> {
        self.tick()?;
        self.bus.write_reg(reg, value).map_err(|_| ())
    }
    fn read_regs(&mut self, reg: u8, buf: &mut [u8]) -> Result<(), ()> {
        self.tick()?;
        self.bus.read_regs(reg, buf).map_err(|_| ())
    }
}

#[test]
fn an_overflow_is_never_forgotten_whichever_transfer_fails() {
    // The count read finds 512 bytes; the reset that follows checks the
    // configuration and takes five more transfers. Fail each of the seven
    // in turn.
    for n in 1..=7 {
        let cfg = Config::default();
        let chip = counting(cfg);
        let delay = chip.delay();
        let bus = FailNth {
            bus: I2cBus::new(chip, ADDRESS),
            fail: 0,
        };
        let mut imu = Mpu9250::new(bus, delay).unwrap();
        imu.configure(cfg).unwrap();
        imu.bus_mut().bus.inner_mut().advance(1.0);
        imu.bus_mut().fail = n;
        let mut frames = Vec::new();
        assert!(read_words(&mut imu, &mut frames).is_err(), "transfer {n}");
        assert_eq!(
            read_words(&mut imu, &mut frames).unwrap(),
            FifoRead::Overflow,
            "transfer {n}"
        );
        assert!(frames.is_empty());
        imu.bus_mut().bus.inner_mut().advance(0.05);
        assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(10));
        let first = frames[0][0];
        assert!(
            frames
                .iter()
                .enumerate()
                .all(|(i, f)| *f == [first + i as i16; 7]),
            "transfer {n}"
        );
    }
}

#[test]
fn a_frame_arriving_during_the_burst_into_a_full_fifo_is_caught() {
    // 1 kHz into a 400 kHz I2C bus: the 505-byte burst takes 11 ms, while
    // the FIFO, holding 36 frames, is full at the next one.
    let cfg = Config {
        rate_hz: 1000.0,
        ..Config::default()
    };
    let mut imu = imu_on_i2c(counting(cfg).with_bus_clock(400e3), ADDRESS).unwrap();
    imu.configure(cfg).unwrap();
    let chip =
        |imu: &mut Mpu9250<I2cBus<SimChip>, SimDelay>| -> SimStats { imu.bus_mut().inner_mut().stats() };
    // Just after the 36th frame: the 37th is due in about 1 ms, after the
    // 0.1 ms count read and early in the 11 ms burst.
    while imu.bus_mut().inner_mut().fifo_len() < 504 {
        imu.bus_mut().inner_mut().advance(50e-6);
    }
    let mut frames = Vec::new();
    let r = read_words(&mut imu, &mut frames).unwrap();
    assert_eq!(r, FifoRead::Overflow, "{} frames read", frames.len());
    assert!(frames.is_empty(), "no frame from the overrun burst is kept");
    assert!(chip(&mut imu).overflows >= 1);
    // The stream resumes whole.
    imu.bus_mut().inner_mut().advance(0.010);
    read_words(&mut imu, &mut frames).unwrap();
    assert!(!frames.is_empty());
    assert!(frames.iter().all(|f| f.iter().all(|&v| v == f[0])), "{frames:?}");
}

#[test]
fn a_lost_reply_to_the_status_read_drops_the_unvouched_burst() {
    let cfg = Config::default();
    let mut imu = imu_on_spi(counting(cfg)).unwrap();
    imu.configure(cfg).unwrap();
    let mut frames = Vec::new();
    imu.bus_mut().inner_mut().advance(0.1);
    imu.bus_mut()
        .inner_mut()
        .fail_next_read(mpu9250::regs::INT_STATUS, SimError::ShortRead(1));
    assert!(read_words(&mut imu, &mut frames).is_err());
    assert!(frames.is_empty());
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Resync);
    imu.bus_mut().inner_mut().advance(0.05);
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(10));
    assert_eq!(frames[0], [20; 7], "samples 0..20 went with the reset");
}

#[test]
fn a_brown_out_during_a_failed_read_is_configured_again_not_read_at_defaults() {
    let cfg = Config {
        gyro_range: GyroRange::Dps2000,
        accel_range: AccelRange::G16,
        ..Config::default()
    };
    let mut imu = configured(cfg);
    let mut frames = Vec::new();
    imu.bus_mut().inner_mut().advance(0.1);
    // A supply dip breaks off a burst and resets the chip.
    imu.bus_mut()
        .inner_mut()
        .fail_next_fifo_read(SimError::ShortRead(20));
    assert!(read_words(&mut imu, &mut frames).is_err());
    imu.bus_mut().inner_mut().power_cycle();
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Reconfigured);
    // The chip runs at 200 Hz and ±2000 °/s, ±16 g again: 10 frames in 50 ms,
    // each whole, at the configured scale (sample k reads k LSB).
    imu.bus_mut().inner_mut().advance(0.05);
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(10));
    let si = imu.config().sample(&RawFrame::from(frames[0])).to_log_row();
    let k = f64::from(frames[0][0]);
    assert!((si[3] - k * GyroRange::Dps2000.lsb_rad()).abs() < 1e-12, "{si:?}");
    assert!((si[0] - k * AccelRange::G16.lsb_si()).abs() < 1e-12, "{si:?}");
    assert!(frames.iter().all(|f| f.iter().all(|&v| v == f[0])));
}

#[test]
fn spi_reads_the_same_chip() {
    let cfg = Config::default();
    let mut imu = imu_on_spi(counting(cfg)).unwrap();
    imu.configure(cfg).unwrap();
    imu.bus_mut().inner_mut().advance(0.1);
    let mut frames = Vec::new();
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(20));
    assert!(
        frames
            .iter()
            .enumerate()
            .all(|(k, f)| f.iter().all(|&v| v == k as i16))
    );
}

/// A delay that does not wait: a driver that skipped the start-up time.
struct NoWait;

impl embedded_hal::delay::DelayNs for NoWait {
    fn delay_ns(&mut self, _: u32) {}
}

#[test]
fn after_a_reset_the_chip_answers_only_once_its_start_up_time_has_passed() {
    use embedded_hal::i2c::I2c;
    use mpu9250::regs;
    // The chip itself: H_RESET, then nothing answers for the typical
    // start-up time (PS-MPU-9250A-01 §3.4.2: 11 ms), then it does.
    let mut chip = SimChip::new(Box::new(|_, _| [0.0; 7]));
    chip.write(ADDRESS, &[regs::PWR_MGMT_1, regs::H_RESET]).unwrap();
    let mut id = [0u8];
    assert_eq!(
        chip.write_read(ADDRESS, &[regs::WHO_AM_I], &mut id),
        Err(SimError::Nack)
    );
    chip.advance(0.010);
    assert_eq!(
        chip.write_read(ADDRESS, &[regs::WHO_AM_I], &mut id),
        Err(SimError::Nack)
    );
    chip.advance(0.002);
    chip.write_read(ADDRESS, &[regs::WHO_AM_I], &mut id).unwrap();
    assert_eq!(id[0], regs::ID_MPU9250);
    // The driver waits it out, on I2C and on SPI…
    let cfg = Config::default();
    let mut imu = configured(cfg);
    imu.bus_mut().inner_mut().advance(0.05);
    let mut frames = Vec::new();
    assert_eq!(read_words(&mut imu, &mut frames).unwrap(), FifoRead::Frames(10));
    let mut imu = imu_on_spi(counting(cfg)).unwrap();
    imu.configure(cfg).unwrap();
    // …and one that does not is refused by the chip.
    let mut hasty = Mpu9250::new(I2cBus::new(counting(cfg), ADDRESS), NoWait).unwrap();
    assert!(matches!(hasty.configure(cfg), Err(Error::Bus(SimError::Nack))));
    let mut hasty = Mpu9250::new(SpiBus::new(counting(cfg)), NoWait).unwrap();
    assert!(matches!(hasty.configure(cfg), Err(Error::Bus(_))));
}

#[test]
fn a_rate_the_chip_cannot_make_is_a_typed_error() {
    // 1 kHz / 500: SMPLRT_DIV would be 499, beyond its 8 bits.
    let cfg = Config {
        rate_hz: 2.0,
        ..Config::default()
    };
    let mut imu = imu_on_i2c(counting(cfg), ADDRESS).unwrap();
    let e = imu.configure(cfg).unwrap_err();
    assert!(
        matches!(e, Error::Config(mpu9250::driver::ConfigError::Rate { hz }) if hz == 2.0),
        "{e:?}"
    );
    assert_eq!(e.to_string(), "2 Hz cannot be made as 1 kHz / (1 + SMPLRT_DIV)");
}
