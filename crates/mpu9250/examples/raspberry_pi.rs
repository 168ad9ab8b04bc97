//! An MPU-9250 on a Raspberry Pi's I2C header (SDA pin 3, SCL pin 5, AD0
//! low: address 0x68), read through its FIFO for a second:
//!
//! ```text
//! cargo run -p mpu9250 --example raspberry_pi [/dev/i2c-1]
//! ```
//!
//! I2C must be enabled (`raspi-config`, or `dtparam=i2c_arm=on`), and the
//! user in the `i2c` group. `imutherm record` does the same for hours, with
//! gaps, retries and a log file.

#[cfg(target_os = "linux")]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    use linux_embedded_hal::{Delay, I2cdev};
    use mpu9250::config::Config;
    use mpu9250::driver::{FifoRead, I2cBus, Mpu9250};

    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "/dev/i2c-1".to_string());
    let i2c = I2cdev::new(&path).map_err(|e| format!("opening {path}: {e}"))?;
    // `Delay` waits out the chip's start-up after its reset.
    let mut imu = Mpu9250::new(I2cBus::new(i2c, 0x68), Delay).map_err(|e| format!("{path}: {e}"))?;
    let config = Config {
        rate_hz: 200.0,
        ..Config::default()
    };
    imu.configure(config).map_err(|e| e.to_string())?;
    println!("{} on {path}, {} Hz", imu.chip().name(), config.rate_hz);
    let mut frames = Vec::new();
    // 20 ms between reads: the 512-byte FIFO holds 36 frames, 180 ms at 200 Hz.
    for _ in 0..50 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        match imu.read_frames(&mut frames) {
            Ok(FifoRead::Frames(_)) => {}
            Ok(lost) => println!("samples lost: {lost:?}"),
            Err(e) => println!("bus error, retried at the next read: {e}"),
        }
    }
    println!("{} frames in 1 s", frames.len());
    if let Some(last) = frames.last() {
        let s = config.sample(last);
        let ([ax, ay, az], [gx, gy, gz]) = (s.accel, s.gyro);
        println!(
            "last: accel {ax:.3} {ay:.3} {az:.3} m/s², gyro {gx:.4} {gy:.4} {gz:.4} rad/s, {:.2} °C",
            s.temp_c
        );
    }
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn main() {
    eprintln!("this example reads Linux's i2c-dev: run it on a Raspberry Pi");
}
