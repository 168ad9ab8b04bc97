//! The driver: generic over the bus and the delay, owns both
//! (`new(bus, delay)`, `release()`).

use embedded_hal::delay::DelayNs;
use embedded_hal::i2c::{Error as _, ErrorKind, I2c, NoAcknowledgeSource};
use embedded_hal::spi::{Operation, SpiDevice};

use crate::config::Config;
use crate::frame::RawFrame;
use crate::regs;

/// Register access over I2C or SPI.
pub trait Bus {
    /// The bus's error.
    type Error: core::fmt::Debug;
    /// Writes one register.
    fn write_reg(&mut self, reg: u8, value: u8) -> Result<(), Self::Error>;
    /// Reads consecutive registers (or the FIFO port) in one burst.
    fn read_regs(&mut self, reg: u8, buf: &mut [u8]) -> Result<(), Self::Error>;
    /// USER_CTRL bits the bus needs kept set: on SPI, I2C_IF_DIS, so that
    /// the chip's I2C slave cannot misread SPI traffic.
    fn user_ctrl_bits(&self) -> u8 {
        0
    }
    /// Whether `error` proves the chip saw nothing of the transfer, so that
    /// a FIFO read that failed with it took no byte out of the FIFO. Only an
    /// I2C address NACK proves that; anything else (a NACK on data, a short
    /// read, any SPI error) may have left the FIFO part-read.
    fn nothing_transferred(_error: &Self::Error) -> bool {
        false
    }
}

/// The chip on an I2C bus at 0x68 (AD0 low) or 0x69 (AD0 high).
#[derive(Debug)]
pub struct I2cBus<I> {
    i2c: I,
    address: u8,
}

impl<I> I2cBus<I> {
    /// The bus and the chip's address.
    pub fn new(i2c: I, address: u8) -> Self {
        I2cBus { i2c, address }
    }

    /// Gives the bus back.
    pub fn release(self) -> I {
        self.i2c
    }

    /// The bus itself (a simulated chip's clock is advanced through it).
    pub fn inner_mut(&mut self) -> &mut I {
        &mut self.i2c
    }
}

impl<I: I2c> Bus for I2cBus<I> {
    type Error = I::Error;

    fn write_reg(&mut self, reg: u8, value: u8) -> Result<(), Self::Error> {
        self.i2c.write(self.address, &[reg, value])
    }

    fn read_regs(&mut self, reg: u8, buf: &mut [u8]) -> Result<(), Self::Error> {
        self.i2c.write_read(self.address, &[reg], buf)
    }

    fn nothing_transferred(error: &Self::Error) -> bool {
        // Linux reports ENXIO this way: the address phase got no ACK.
        error.kind() == ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
    }
}

/// The chip on an SPI device (mode 0 or 3; ≤ 1 MHz for the configuration
/// registers, ≤ 20 MHz for sensor data: the device's clock is set by its
/// owner).
#[derive(Debug)]
pub struct SpiBus<S> {
    spi: S,
}

impl<S> SpiBus<S> {
    /// The SPI device.
    pub fn new(spi: S) -> Self {
        SpiBus { spi }
    }

    /// Gives the device back.
    pub fn release(self) -> S {
        self.spi
    }

    /// The device itself.
    pub fn inner_mut(&mut self) -> &mut S {
        &mut self.spi
    }
}

impl<S: SpiDevice> Bus for SpiBus<S> {
    type Error = S::Error;

    fn write_reg(&mut self, reg: u8, value: u8) -> Result<(), Self::Error> {
        self.spi.write(&[reg & !regs::SPI_READ, value])
    }

    fn read_regs(&mut self, reg: u8, buf: &mut [u8]) -> Result<(), Self::Error> {
        self.spi
            .transaction(&mut [Operation::Write(&[reg | regs::SPI_READ]), Operation::Read(buf)])
    }

    fn user_ctrl_bits(&self) -> u8 {
        regs::I2C_IF_DIS
    }
}

/// Waits by sleeping the thread (a host with an operating system).
#[cfg(feature = "std")]
#[derive(Debug, Clone, Copy, Default)]
pub struct StdDelay;

#[cfg(feature = "std")]
impl DelayNs for StdDelay {
    fn delay_ns(&mut self, ns: u32) {
        std::thread::sleep(std::time::Duration::from_nanos(u64::from(ns)));
    }
}

/// Which chip answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Chip {
    /// MPU-9250 (WHO_AM_I 0x71).
    Mpu9250,
    /// MPU-9255 (0x73).
    Mpu9255,
    /// MPU-6500 (0x70).
    Mpu6500,
}

impl Chip {
    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Chip::Mpu9250 => "MPU-9250",
            Chip::Mpu9255 => "MPU-9255",
            Chip::Mpu6500 => "MPU-6500",
        }
    }
}

/// A configuration the chip cannot do.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// The output rate is not 1 kHz / (1 + n) for any n in 0…255.
    #[error("{hz} Hz cannot be made as 1 kHz / (1 + SMPLRT_DIV)")]
    Rate {
        /// The rate asked for, Hz.
        hz: f64,
    },
}

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum Error<E: core::fmt::Debug> {
    /// The bus failed (NACK, short transfer…).
    #[error("bus error: {0:?}")]
    Bus(E),
    /// Something answered that is not an MPU-9250 family chip.
    #[error("WHO_AM_I is 0x{0:02x}: not an MPU-9250, MPU-9255 or MPU-6500")]
    UnknownDevice(u8),
    /// A configuration the chip cannot do.
    #[error(transparent)]
    Config(#[from] ConfigError),
}

/// What one FIFO read brought.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FifoRead {
    /// This many whole frames were appended.
    Frames(usize),
    /// The FIFO overflowed since the last read: its content was discarded
    /// (512 is not a multiple of 14, so frame alignment was lost) and the
    /// FIFO reset; the samples in between are lost.
    Overflow,
    /// At a FIFO reset the chip was found with its configuration gone (a
    /// brown-out resets its registers): it was configured again, and the
    /// samples since the last read are lost.
    Reconfigured,
    /// An earlier FIFO read failed part-way (or the count made no sense), so
    /// frame alignment was unknown: the FIFO was reset, and the samples since
    /// the last whole read are lost.
    Resync,
}

/// Further tries of the status read that vouches for a burst, when the bus
/// proves it never reached the chip.
const POST_CHECK_RETRIES: u32 = 3;

/// Why the FIFO must be reset before it can be read again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pending {
    Overflow,
    Resync,
}

/// The driver.
#[derive(Debug)]
pub struct Mpu9250<B, D> {
    bus: B,
    /// Waits out the chip's start-up after a reset.
    delay: D,
    chip: Chip,
    config: Config,
    /// The last burst's bytes: `scratch[..scratch_len]`. A fixed array, as
    /// the FIFO never holds more, so the driver needs no allocator.
    scratch: [u8; regs::FIFO_BYTES],
    scratch_len: usize,
    /// A reset owed: INT_STATUS clears on read, so an overflow seen in a
    /// read that then failed must not be forgotten, and a data burst that
    /// failed part-way leaves the FIFO misaligned.
    pending: Option<Pending>,
    fifo_level: usize,
    /// `configure` has run: the registers can be checked against `config`.
    configured: bool,
}

impl<B: Bus, D: DelayNs> Mpu9250<B, D> {
    /// Probes the chip: WHO_AM_I must name an MPU-9250 family member. The
    /// delay waits out the chip's start-up after each reset.
    pub fn new(mut bus: B, delay: D) -> Result<Self, Error<B::Error>> {
        let mut id = [0u8];
        bus.read_regs(regs::WHO_AM_I, &mut id).map_err(Error::Bus)?;
        let chip = match id[0] {
            regs::ID_MPU9250 => Chip::Mpu9250,
            regs::ID_MPU9255 => Chip::Mpu9255,
            regs::ID_MPU6500 => Chip::Mpu6500,
            other => return Err(Error::UnknownDevice(other)),
        };
        Ok(Mpu9250 {
            bus,
            delay,
            chip,
            config: Config::default(),
            scratch: [0; regs::FIFO_BYTES],
            scratch_len: 0,
            pending: None,
            fifo_level: 0,
            configured: false,
        })
    }

    /// The chip that answered.
    pub fn chip(&self) -> Chip {
        self.chip
    }

    /// The configuration in force.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Gives the bus and the delay back.
    pub fn release(self) -> (B, D) {
        (self.bus, self.delay)
    }

    /// Bytes the FIFO held at the last count read (0…512).
    pub fn fifo_level(&self) -> usize {
        self.fifo_level
    }

    /// The bus, without giving it up.
    pub fn bus_mut(&mut self) -> &mut B {
        &mut self.bus
    }

    /// Resets the chip and sets it up: clock, filters, full scales, rate,
    /// and the FIFO with accelerometer, temperature and gyroscope.
    pub fn configure(&mut self, config: Config) -> Result<(), Error<B::Error>> {
        let div = config.divider().ok_or(ConfigError::Rate { hz: config.rate_hz })?;
        let w = |bus: &mut B, reg, val| bus.write_reg(reg, val).map_err(Error::Bus);
        w(&mut self.bus, regs::PWR_MGMT_1, regs::H_RESET)?;
        // The chip ignores the bus until its start-up is through.
        self.delay.delay_ms(regs::START_UP_MS);
        w(&mut self.bus, regs::PWR_MGMT_1, regs::CLKSEL_AUTO)?;
        w(&mut self.bus, regs::PWR_MGMT_2, 0)?;
        // FIFO_MODE cleared: on overflow the oldest bytes go, which the
        // overflow flag reports.
        w(&mut self.bus, regs::CONFIG, config.dlpf_cfg())?;
        w(&mut self.bus, regs::SMPLRT_DIV, div)?;
        w(&mut self.bus, regs::GYRO_CONFIG, config.gyro_range.bits())?;
        w(&mut self.bus, regs::ACCEL_CONFIG, config.accel_range.bits())?;
        w(&mut self.bus, regs::ACCEL_CONFIG2, config.dlpf_cfg())?;
        w(&mut self.bus, regs::INT_ENABLE, regs::FIFO_OFLOW_EN)?;
        self.config = config;
        self.configured = true;
        self.start_fifo()
    }

    /// The FIFO start sequence (FIFO_EN = 0, reset, enable, clear the
    /// status, select the sensors).
    pub fn start_fifo(&mut self) -> Result<(), Error<B::Error>> {
        let mut status = [0u8];
        self.bus.write_reg(regs::FIFO_EN, 0).map_err(Error::Bus)?;
        let keep = self.bus.user_ctrl_bits();
        self.bus
            .write_reg(regs::USER_CTRL, keep | regs::FIFO_RST)
            .map_err(Error::Bus)?;
        self.bus
            .write_reg(regs::USER_CTRL, keep | regs::USER_FIFO_EN)
            .map_err(Error::Bus)?;
        self.bus
            .read_regs(regs::INT_STATUS, &mut status)
            .map_err(Error::Bus)?;
        self.bus
            .write_reg(regs::FIFO_EN, regs::FIFO_ALL)
            .map_err(Error::Bus)
    }

    /// Reads whole frames from the FIFO into `out`, at most `out.len()` of
    /// them, each a [`RawFrame`] (the accelerometer, temperature and
    /// gyroscope counts by name); `Frames(n)` says how many were written.
    /// Never splits a frame: a partial frame, and the frames `out` has no
    /// room for, stay in the FIFO for the next read. A slice of
    /// [`regs::FIFO_FRAMES`] always has room for the whole FIFO. It needs
    /// no allocator.
    ///
    /// Three transfers: FIFO_COUNT (512 means an overflow: the FIFO is
    /// reset), the burst of whole frames, and INT_STATUS, whose overflow
    /// flag says whether a frame arriving during the burst pushed out bytes
    /// it was reading (then the frames are dropped and the FIFO reset).
    ///
    /// A bus error is returned as it is, and the call can simply be retried:
    /// if the error may have taken bytes out of the FIFO (anything but an
    /// address NACK) or left the burst unverified, the next call resets the
    /// FIFO and says why ([`FifoRead::Resync`]) instead of decoding bytes it
    /// cannot vouch for.
    ///
    /// [`Mpu9250::read_frames`] appends every whole frame to a `Vec`.
    pub fn read_frames_into(&mut self, out: &mut [RawFrame]) -> Result<FifoRead, Error<B::Error>> {
        let read = self.read_whole_frames(out.len())?;
        if let FifoRead::Frames(_) = read {
            for (slot, frame) in out.iter_mut().zip(self.frames_read()) {
                *slot = frame;
            }
        }
        Ok(read)
    }

    /// As [`Mpu9250::read_frames_into`], appending every whole frame in the
    /// FIFO to `out`.
    #[cfg(feature = "std")]
    pub fn read_frames(&mut self, out: &mut Vec<RawFrame>) -> Result<FifoRead, Error<B::Error>> {
        let read = self.read_whole_frames(regs::FIFO_FRAMES)?;
        if let FifoRead::Frames(_) = read {
            out.extend(self.frames_read());
        }
        Ok(read)
    }

    /// The frames the last successful burst brought, decoded.
    fn frames_read(&self) -> impl Iterator<Item = RawFrame> + '_ {
        let (frames, _) = self.scratch[..self.scratch_len].as_chunks::<{ regs::FRAME_BYTES }>();
        frames.iter().map(RawFrame::from_be_bytes)
    }

    /// The transfers of a FIFO read of at most `room` frames; on
    /// `Frames(n)`, `scratch` holds the n frames' bytes.
    fn read_whole_frames(&mut self, room: usize) -> Result<FifoRead, Error<B::Error>> {
        if let Some(cause) = self.pending {
            return self.resync(cause);
        }
        // The count alone says whether the FIFO overflowed since the last
        // read: it stays at 512 (no whole number of frames) until read. So
        // no status read is needed before it, and none can be lost.
        let mut count = [0u8; 2];
        self.bus
            .read_regs(regs::FIFO_COUNTH, &mut count)
            .map_err(Error::Bus)?;
        let bytes = (usize::from(count[0]) << 8 | usize::from(count[1])) & 0x1FFF;
        self.fifo_level = bytes;
        if bytes >= regs::FIFO_BYTES {
            // 512 is no whole number of frames: the FIFO overflowed since
            // the status was read. More is a corrupt count.
            let cause = if bytes == regs::FIFO_BYTES {
                Pending::Overflow
            } else {
                Pending::Resync
            };
            return self.resync(cause);
        }
        let frames = (bytes / regs::FRAME_BYTES).min(room);
        self.scratch_len = frames * regs::FRAME_BYTES;
        if frames == 0 {
            return Ok(FifoRead::Frames(0));
        }
        if let Err(e) = self
            .bus
            .read_regs(regs::FIFO_R_W, &mut self.scratch[..self.scratch_len])
        {
            if !B::nothing_transferred(&e) {
                self.pending = Some(Pending::Resync);
            }
            return Err(Error::Bus(e));
        }
        // A frame that arrived into a full FIFO between the count and the
        // end of the burst pushed out bytes the burst was reading: only a
        // status read after it says the frames are whole.
        let mut check = self.overflowed();
        for _ in 0..POST_CHECK_RETRIES {
            match &check {
                // An address NACK left the flag as it was: ask again.
                Err(Error::Bus(e)) if B::nothing_transferred(e) => check = self.overflowed(),
                _ => break,
            }
        }
        match check {
            Ok(false) => {}
            Ok(true) => return self.resync(Pending::Overflow),
            Err(e) => {
                // The flag may be gone with the failed read: the frames
                // cannot be vouched for. They are dropped, and their loss
                // is recorded by the reset the next call makes.
                self.pending = Some(Pending::Resync);
                return Err(e);
            }
        }
        Ok(FifoRead::Frames(frames))
    }

    /// Whether SMPLRT_DIV, CONFIG, GYRO_CONFIG and ACCEL_CONFIG still hold
    /// what `configure` wrote.
    fn configuration_intact(&mut self) -> Result<bool, Error<B::Error>> {
        let mut got = [0u8; 4];
        self.bus
            .read_regs(regs::SMPLRT_DIV, &mut got)
            .map_err(Error::Bus)?;
        let c = &self.config;
        let want = [
            c.divider().unwrap_or(0),
            c.dlpf_cfg(),
            c.gyro_range.bits(),
            c.accel_range.bits(),
        ];
        Ok(got == want)
    }

    /// Reads (and so clears) FIFO_OFLOW_INT.
    fn overflowed(&mut self) -> Result<bool, Error<B::Error>> {
        let mut status = [0u8];
        self.bus
            .read_regs(regs::INT_STATUS, &mut status)
            .map_err(Error::Bus)?;
        Ok(status[0] & regs::FIFO_OFLOW_INT != 0)
    }

    /// Resets the FIFO, remembering the cause until the reset is through.
    /// A failure that forced the reset may have come with a brown-out, which
    /// leaves the chip at its power-on defaults (1 kHz, ±250 °/s, ±2 g) still
    /// filling a FIFO once restarted: the configuration is checked first and
    /// written again if it is gone.
    fn resync(&mut self, cause: Pending) -> Result<FifoRead, Error<B::Error>> {
        self.pending = Some(cause);
        if self.configured && !self.configuration_intact()? {
            self.configure(self.config)?;
            self.pending = None;
            self.fifo_level = 0;
            return Ok(FifoRead::Reconfigured);
        }
        self.start_fifo()?;
        self.pending = None;
        self.fifo_level = 0;
        Ok(match cause {
            Pending::Overflow => FifoRead::Overflow,
            Pending::Resync => FifoRead::Resync,
        })
    }
}
