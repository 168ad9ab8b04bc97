//! The register map (InvenSense RM-MPU-9250A-00 rev 1.4) and its bit fields.

/// Sample rate divider: rate = internal rate / (1 + SMPLRT_DIV).
pub const SMPLRT_DIV: u8 = 0x19;
/// FIFO mode (bit 6) and gyro DLPF_CFG (bits 2:0).
pub const CONFIG: u8 = 0x1A;
/// Gyro full scale (bits 4:3) and FCHOICE_B (bits 1:0).
pub const GYRO_CONFIG: u8 = 0x1B;
/// Accelerometer full scale (bits 4:3).
pub const ACCEL_CONFIG: u8 = 0x1C;
/// Accelerometer DLPF (A_DLPF_CFG, bits 2:0; ACCEL_FCHOICE_B bit 3).
pub const ACCEL_CONFIG2: u8 = 0x1D;
/// Which sensors feed the FIFO.
pub const FIFO_EN: u8 = 0x23;
/// Interrupt enable; bit 4 FIFO_OFLOW_EN.
pub const INT_ENABLE: u8 = 0x38;
/// Interrupt status; bit 4 FIFO_OFLOW_INT, cleared on read.
pub const INT_STATUS: u8 = 0x3A;
/// First data register: ACCEL_XOUT_H … GYRO_ZOUT_L follow (14 bytes).
pub const ACCEL_XOUT_H: u8 = 0x3B;
/// FIFO enable (bit 6), FIFO reset (bit 2), I2C interface disable (bit 4).
pub const USER_CTRL: u8 = 0x6A;
/// Device reset (bit 7), sleep (bit 6), clock source (bits 2:0).
pub const PWR_MGMT_1: u8 = 0x6B;
/// Sensor standby bits.
pub const PWR_MGMT_2: u8 = 0x6C;
/// FIFO count, high byte (read with the low byte as one burst: the high
/// byte latches both).
pub const FIFO_COUNTH: u8 = 0x72;
/// FIFO count, low byte.
pub const FIFO_COUNTL: u8 = 0x73;
/// FIFO data port.
pub const FIFO_R_W: u8 = 0x74;
/// Device identity.
pub const WHO_AM_I: u8 = 0x75;

/// WHO_AM_I of the MPU-9250.
pub const ID_MPU9250: u8 = 0x71;
/// WHO_AM_I of the MPU-9255.
pub const ID_MPU9255: u8 = 0x73;
/// WHO_AM_I of the MPU-6500 (the MPU-9250 without magnetometer).
pub const ID_MPU6500: u8 = 0x70;

/// PWR_MGMT_1: reset every register.
pub const H_RESET: u8 = 0x80;
/// PWR_MGMT_1: best available clock (PLL when ready).
pub const CLKSEL_AUTO: u8 = 0x01;
/// USER_CTRL: FIFO enable.
pub const USER_FIFO_EN: u8 = 0x40;
/// USER_CTRL: disable I2C (SPI only).
pub const I2C_IF_DIS: u8 = 0x10;
/// USER_CTRL: FIFO reset.
pub const FIFO_RST: u8 = 0x04;
/// FIFO_EN: temperature, gyro x/y/z, accelerometer.
pub const FIFO_ALL: u8 = 0xF8;
/// INT_STATUS: FIFO overflow.
pub const FIFO_OFLOW_INT: u8 = 0x10;
/// INT_ENABLE: FIFO overflow interrupt enable (so that the status bit is
/// certain to be raised, whatever a part does with disabled sources).
pub const FIFO_OFLOW_EN: u8 = 0x10;
/// CONFIG: when set, a full FIFO keeps its data and drops new samples;
/// clear (as imutherm uses it), new data replace the oldest bytes.
pub const FIFO_MODE: u8 = 0x40;

/// FIFO size in bytes.
pub const FIFO_BYTES: usize = 512;
/// One FIFO frame: ACCEL_X..Z, TEMP, GYRO_X..Z, big-endian i16.
pub const FRAME_BYTES: usize = 14;
/// Whole frames the FIFO can hold (36; 512 is no multiple of 14).
pub const FIFO_FRAMES: usize = FIFO_BYTES / FRAME_BYTES;
/// SPI: the read bit set in the register address.
pub const SPI_READ: u8 = 0x80;
/// Internal sample rate with the DLPF on (DLPF_CFG 1–6, FCHOICE_B = 00), Hz.
pub const INTERNAL_RATE_HZ: f64 = 1000.0;
/// Temperature sensitivity, LSB/°C (PS-MPU-9250A-01 §3.4.2).
pub const TEMP_LSB_PER_C: f64 = 333.87;
/// Temperature offset: 0 LSB reads 21 °C.
pub const TEMP_OFFSET_C: f64 = 21.0;

/// The wait after H_RESET before the registers can be written again, ms:
/// the maximum "start-up time for register read/write" (typical 11 ms, at
/// most 100 ms; PS-MPU-9250A-01 rev 1.0 §3.4.2, A.C. Electrical
/// Characteristics). H_RESET restores every register to its power-on value
/// (RM-MPU-9250A-00, register 107, PWR_MGMT_1), and the chip does not answer until
/// it is through.
pub const START_UP_MS: u32 = 100;

/// The typical start-up time, s (same table): what the simulated chip
/// takes before it answers again after H_RESET.
pub const START_UP_TYPICAL_S: f64 = 0.011;
