//! The compensation-model loader on arbitrary text, and every model it
//! accepts applied to a short recording and exported for both firmwares:
//! refused or applied, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use thermal::firmware::{Firmware, Target, export};
use thermal::tcal::Model;

fuzz_target!(|text: &str| {
    // A model that parses but fails validation must still be refused by
    // apply and export, never reach `f64::clamp` with reversed bounds
    // (corpus/tcal_model/reversed_range.json is the input that once did).
    let Ok(model) = serde_json::from_str::<Model>(text) else {
        return;
    };
    let valid = Model::from_json(text).is_ok();
    let temp: Vec<f64> = (0..64).map(|i| 20.0 + i as f64 * 0.5).collect();
    for ch in &model.channels {
        let mut data = vec![0.01; temp.len()];
        let applied = model.apply(&ch.name, &mut data, &temp, 100.0);
        if !valid {
            assert!(applied.is_err(), "an invalid model was applied");
        } else if applied.is_ok() {
            assert!(data.iter().all(|v| v.is_finite()), "finite in, not finite out");
        }
    }
    for firmware in [Firmware::Px4, Firmware::ArduPilot] {
        let exported = export(&model, firmware, Target { instance: None, device_id: None });
        if !valid {
            assert!(exported.is_err(), "an invalid model was exported");
        }
    }
    let _ = serde_json::to_string(&model);
});
