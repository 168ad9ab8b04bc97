//! The driver's bus traffic, transfer by transfer, against the register
//! map (InvenSense RM-MPU-9250A-00 rev 1.4, "RM" below): every address and
//! bit is written out from the register map, not taken from the driver's
//! `regs`.

use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as Wait};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use embedded_hal_mock::eh1::spi::{Mock as SpiMock, Transaction as Spi};

use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{FifoRead, I2cBus, Mpu9250, SpiBus};

/// AD0 low: 1101000 (PS-MPU-9250A-01 §3.4.2, I2C ADDRESS).
const AD: u8 = 0x68;

/// WHO_AM_I (0x75) answers 0x71 for an MPU-9250 (RM register 117).
fn probe() -> I2c {
    I2c::write_read(AD, vec![0x75], vec![0x71])
}

/// The FIFO start: FIFO_EN (0x23) off, USER_CTRL (0x6A) FIFO_RST (bit 2),
/// then FIFO_EN (bit 6), INT_STATUS (0x3A) read to clear it, FIFO_EN with
/// TEMP, XG, YG, ZG and ACCEL (bits 7…3: 0xF8) (RM registers 35, 58,
/// 106).
fn fifo_start() -> Vec<I2c> {
    vec![
        I2c::write(AD, vec![0x23, 0x00]),
        I2c::write(AD, vec![0x6A, 0x04]),
        I2c::write(AD, vec![0x6A, 0x40]),
        I2c::write_read(AD, vec![0x3A], vec![0x00]),
        I2c::write(AD, vec![0x23, 0xF8]),
    ]
}

/// ±2000 °/s, ±16 g, 100 Hz, a 41 Hz low-pass.
fn config() -> Config {
    Config {
        gyro_range: GyroRange::Dps2000,
        accel_range: AccelRange::G16,
        rate_hz: 100.0,
        dlpf_hz: Some(41.0),
    }
}

/// `configure` with [`config`]: H_RESET, the start-up wait, then each
/// register once.
fn configure_traffic() -> Vec<I2c> {
    let mut t = vec![
        probe(),
        // PWR_MGMT_1 (0x6B): H_RESET (bit 7) (RM register 107)…
        I2c::write(AD, vec![0x6B, 0x80]),
        // …then CLKSEL = 1, the PLL when ready.
        I2c::write(AD, vec![0x6B, 0x01]),
        // PWR_MGMT_2 (0x6C): every axis on (RM register 108).
        I2c::write(AD, vec![0x6C, 0x00]),
        // CONFIG (0x1A): DLPF_CFG 3, 41 Hz (RM register 26).
        I2c::write(AD, vec![0x1A, 0x03]),
        // SMPLRT_DIV (0x19): 1 kHz / (1 + 9) = 100 Hz (RM register 25).
        I2c::write(AD, vec![0x19, 9]),
        // GYRO_CONFIG (0x1B): GYRO_FS_SEL 3 in bits 4:3 (RM register 27).
        I2c::write(AD, vec![0x1B, 0x18]),
        // ACCEL_CONFIG (0x1C): ACCEL_FS_SEL 3 in bits 4:3 (RM register 28).
        I2c::write(AD, vec![0x1C, 0x18]),
        // ACCEL_CONFIG2 (0x1D): A_DLPF_CFG 3 (RM register 29).
        I2c::write(AD, vec![0x1D, 0x03]),
        // INT_ENABLE (0x38): FIFO_OFLOW_EN (bit 4) (RM register 56).
        I2c::write(AD, vec![0x38, 0x10]),
    ];
    t.extend(fifo_start());
    t
}

#[test]
fn configure_resets_waits_out_the_start_up_and_writes_each_register() {
    let mut i2c = I2cMock::new(&configure_traffic());
    // 100 ms: the longest start-up time (PS-MPU-9250A-01 §3.4.2).
    let mut delay = CheckedDelay::new(&[Wait::delay_ms(100)]);
    let mut imu = Mpu9250::new(I2cBus::new(i2c.clone(), AD), delay.clone()).unwrap();
    imu.configure(config()).unwrap();
    i2c.done();
    delay.done();
}

#[test]
fn read_fifo_reads_the_count_whole_frames_and_the_status() {
    let mut t = configure_traffic();
    // Two frames and a half: ACCEL_X…Z, TEMP, GYRO_X…Z big-endian (the
    // FIFO holds the data registers 59…72 in their order, RM register 116).
    let frames: Vec<u8> = (0..28u8).collect();
    t.extend([
        // FIFO_COUNTH/L (0x72, 0x73): 35 bytes (RM registers 114, 115).
        I2c::write_read(AD, vec![0x72], vec![0x00, 35]),
        // FIFO_R_W (0x74): the two whole frames only.
        I2c::write_read(AD, vec![0x74], frames),
        // INT_STATUS: no overflow during the burst.
        I2c::write_read(AD, vec![0x3A], vec![0x00]),
        // 512 bytes: the FIFO overflowed since the last read. The
        // configuration is checked (SMPLRT_DIV…ACCEL_CONFIG in one burst),
        // then the FIFO restarted.
        I2c::write_read(AD, vec![0x72], vec![0x02, 0x00]),
        I2c::write_read(AD, vec![0x19], vec![9, 0x03, 0x18, 0x18]),
    ]);
    t.extend(fifo_start());
    let mut i2c = I2cMock::new(&t);
    let mut delay = CheckedDelay::new(&[Wait::delay_ms(100)]);
    let mut imu = Mpu9250::new(I2cBus::new(i2c.clone(), AD), delay.clone()).unwrap();
    imu.configure(config()).unwrap();
    let mut out = Vec::new();
    assert_eq!(imu.read_frames(&mut out).unwrap(), FifoRead::Frames(2));
    assert_eq!(
        <[i16; 7]>::from(out[0]),
        [0x0001, 0x0203, 0x0405, 0x0607, 0x0809, 0x0A0B, 0x0C0D]
    );
    assert_eq!(out[1].gyro[2], 0x1A1B);
    assert_eq!(imu.read_frames(&mut out).unwrap(), FifoRead::Overflow);
    assert_eq!(out.len(), 2);
    i2c.done();
    delay.done();
}

#[test]
fn on_spi_a_read_sets_bit_7_of_the_address_and_i2c_stays_disabled() {
    // SPI: bit 7 of the first byte set reads (PS-MPU-9250A-01 §7.5);
    // USER_CTRL keeps I2C_IF_DIS (bit 4) in every write (RM register 106).
    let read = |reg: u8, answer: Vec<u8>| {
        [
            Spi::transaction_start(),
            Spi::write_vec(vec![reg | 0x80]),
            Spi::read_vec(answer),
            Spi::transaction_end(),
        ]
    };
    let write = |reg: u8, value: u8| {
        [
            Spi::transaction_start(),
            Spi::write_vec(vec![reg, value]),
            Spi::transaction_end(),
        ]
    };
    let mut t: Vec<Spi<u8>> = Vec::new();
    t.extend(read(0x75, vec![0x71]));
    t.extend(write(0x23, 0x00));
    t.extend(write(0x6A, 0x14));
    t.extend(write(0x6A, 0x50));
    t.extend(read(0x3A, vec![0x00]));
    t.extend(write(0x23, 0xF8));
    let mut spi = SpiMock::new(&t);
    let mut delay = CheckedDelay::new(&[]);
    let mut imu = Mpu9250::new(SpiBus::new(spi.clone()), delay.clone()).unwrap();
    imu.start_fifo().unwrap();
    spi.done();
    delay.done();
}
