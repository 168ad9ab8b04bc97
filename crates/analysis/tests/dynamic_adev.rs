//! The thesis's finding, on a simulated cooling run whose truth is known:
//! the dynamic ADEV at the shortest τ grows from the coldest window to the
//! hottest by the noise factor the simulator was given, within the
//! windows' own confidence intervals.

use analysis::dynamic_adev::{DynamicOptions, dynamic_adev};
use imusim::thermal::Profile;
use imusim::{Simulator, presets};

/// A cooling run from 80 °C towards 34 °C of a white-noise gyro whose noise
/// scales with temperature as the mpu9250-thesis preset's gyro does (1.0 at
/// 34 °C to 1.131 at 82 °C), so that both ends of the run fall between its
/// points and the factor is interpolated at each.
#[test]
fn short_tau_sigma_grows_with_temperature_by_the_simulated_factor() {
    let thesis = presets::preset("mpu9250-thesis").unwrap();
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 20.0;
    cfg.duration_s = 3600.0;
    cfg.seed = 7;
    cfg.profile = Profile::Cooling {
        start_c: 80.0,
        ambient_c: 34.0,
        tau_s: 1800.0,
    };
    cfg.gyro.noise_scale = thesis.gyro.noise_scale.clone();
    let scale = cfg.gyro.clone();
    let sim = Simulator::new(cfg).unwrap();
    let (mut gyro, mut temp) = (Vec::new(), Vec::new());
    sim.run(|c| {
        gyro.extend_from_slice(&c.columns[3]);
        // The temperature as the sensor reports it, as a user has it.
        temp.extend_from_slice(&c.columns[6]);
        Ok(())
    })
    .unwrap();

    // 10-minute windows every minute: short enough that the temperature in
    // each is close to its mean, long enough for a tight interval at τ0.
    // A 95 % level for each end keeps the ratio's interval honest (two
    // 68 % intervals together would miss the truth too often).
    let options = DynamicOptions {
        window_s: 600.0,
        step_s: 60.0,
        confidence: 0.95,
    };
    let d = dynamic_adev(&gyro, &temp, 20.0, &options).unwrap();
    assert_eq!(d.windows.len(), 51);
    assert!(d.skipped.is_empty());
    let (cold, hot) = d.coldest_and_hottest().unwrap();
    // Windows are in time order, and a cooling run is hottest first.
    assert_eq!((hot.start_s, cold.start_s), (0.0, 3000.0));
    assert!(
        hot.t_mean_c > 62.0 && cold.t_mean_c < 43.0,
        "{} {}",
        hot.t_mean_c,
        cold.t_mean_c
    );

    let (h, c) = (hot.points[0], cold.points[0]);
    assert_eq!((h.tau, c.tau), (0.05, 0.05));
    let measured = h.dev / c.dev;
    let lo = h.dev_lo / c.dev_hi;
    let hi = h.dev_hi / c.dev_lo;
    let expected = scale.noise_factor(hot.t_mean_c) / scale.noise_factor(cold.t_mean_c);
    assert!(
        lo <= expected && expected <= hi,
        "σ ratio hot/cold {measured:.4} in [{lo:.4}, {hi:.4}], simulated {expected:.4} \
         ({:.1} °C against {:.1} °C)",
        hot.t_mean_c,
        cold.t_mean_c
    );
    // The growth is seen, not merely allowed: the interval excludes 1.
    assert!(lo > 1.0, "[{lo:.4}, {hi:.4}]");
}
