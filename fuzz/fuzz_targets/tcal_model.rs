//! The compensation-model loader on arbitrary text, and every model it
//! accepts applied to a short recording: refused or applied, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use thermal::tcal::Model;

/// What a model must satisfy before it is applied. The model file is to be
/// validated on load (finite coefficients, t_min < t_max, a positive scale,
/// known and unique channels); until that validation exists, this checks
/// only the known cause of a panic (`f64::clamp` with NaN or reversed
/// bounds), so that the fuzzer looks beyond it: without it the fuzzer finds
/// that panic in well under a second (corpus/tcal_model/reversed_range.json
/// is the input it found). Replace with the model's own validation once it
/// has one.
fn usable(model: &Model) -> bool {
    model.t_min_c <= model.t_max_c
}

fuzz_target!(|text: &str| {
    let Ok(model) = serde_json::from_str::<Model>(text) else {
        return;
    };
    if !usable(&model) {
        return;
    }
    let temp: Vec<f64> = (0..64).map(|i| 20.0 + i as f64 * 0.5).collect();
    for ch in &model.channels {
        let mut data = vec![0.01; temp.len()];
        let _ = model.apply(&ch.name, &mut data, &temp, 100.0);
        let _ = ch.power_coefficients(&model);
    }
    let _ = serde_json::to_string(&model);
});
