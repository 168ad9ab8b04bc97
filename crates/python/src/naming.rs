//! The libraries' settings named as the package's keyword arguments
//! (`rate=200`, `topic='/imu'`); [`install`] runs when the module loads.
//! A setting no function takes (the time column and its unit, a Kalibr
//! file) keeps the name of what it means.

use imu::setting::{Given, Meanings, Naming, Setting, Value};

/// The keyword arguments of `imutherm.read`, `imutherm.tcal_fit` and the
/// model's `evaluate` and `export` (python/imutherm/__init__.py and
/// _tcal.py).
struct Keywords;

impl Naming for Keywords {
    fn name(&self, setting: Setting) -> String {
        keyword(setting).map_or_else(|| Meanings.name(setting), str::to_string)
    }

    fn value(&self, value: &Value) -> String {
        match value {
            Value::Number(v) => v.clone(),
            Value::Text(v) | Value::Spaced(v) => python_str(v),
            Value::Placeholder(v) => (*v).to_string(),
        }
    }

    fn given(&self, setting: Setting, value: &Value) -> String {
        match (setting, keyword(setting)) {
            // `units` is a list or dict: the message names its entry.
            (Setting::UnitOverride, _) => format!("units entry {}", self.value(value)),
            (Setting::Channels, Some(k)) => format!("{k}=[{}]", self.value(value)),
            (_, Some(k)) => format!("{k}={}", self.value(value)),
            (_, None) => Meanings.given(setting, value),
        }
    }

    fn without(&self, settings: &[Setting]) -> String {
        // A switch is turned off, not left out.
        if settings.iter().all(|s| is_switch(*s)) {
            let off: Vec<String> = settings
                .iter()
                .map(|&s| format!("{}=False", self.name(s)))
                .collect();
            format!("with {}", imu::setting::and_list(&off))
        } else {
            let names: Vec<String> = settings.iter().map(|&s| self.name(s)).collect();
            format!("without {}", imu::setting::and_list(&names))
        }
    }

    fn fit_call(&self, given: &Given) -> String {
        format!(
            "`imutherm.tcal_fit(..., {})`",
            self.given(given.setting, &given.value)
        )
    }
}

fn keyword(setting: Setting) -> Option<&'static str> {
    Some(match setting {
        Setting::SampleRate => "rate",
        Setting::UnitOverride => "units",
        Setting::Channels => "channels",
        Setting::Topic => "topic",
        Setting::Instance => "instance",
        Setting::TempTopic => "temp_topic",
        Setting::AllowPartial => "allow_partial",
        Setting::FitOrder => "order",
        Setting::FitFirmware => "firmware",
        Setting::RateTerm => "rate_term",
        Setting::BinWidth => "bin_width",
        Setting::ExportFirmware => "export",
        Setting::DeviceId => "device_id",
        // `tcal_export`'s keyword kept its name.
        Setting::CalibrationSlot => "instance",
        Setting::TimeUnit
        | Setting::ColumnScale
        | Setting::TimeColumn
        | Setting::MaxGridFactor
        | Setting::Overwrite
        | Setting::KalibrFile
        | Setting::NavigationModel => return None,
    })
}

fn is_switch(setting: Setting) -> bool {
    matches!(setting, Setting::AllowPartial | Setting::RateTerm)
}

/// `text` as Python's `repr` writes a `str` of printable characters.
fn python_str(text: &str) -> String {
    let quote = if text.contains('\'') && !text.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut out = String::from(quote);
    for c in text.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c == quote => {
                out.push('\\');
                out.push(c);
            }
            c => out.push(c),
        }
    }
    out.push(quote);
    out
}

/// Names the settings as keyword arguments in every message from now on.
pub(crate) fn install() {
    imu::setting::name_settings(&Keywords);
}

#[cfg(test)]
mod tests {
    use super::*;

    // The messages tests/test_read.py, test_tcal.py and test_tcal_instances.py
    // expect.
    #[test]
    fn settings_render_as_keyword_arguments() {
        let k = Keywords;
        assert_eq!(k.given(Setting::SampleRate, &Value::number(-1.0)), "rate=-1");
        assert_eq!(
            k.given(Setting::UnitOverride, &Value::text("gyro_x=furlong")),
            "units entry 'gyro_x=furlong'"
        );
        assert_eq!(k.given(Setting::Topic, &Value::text("nope")), "topic='nope'");
        assert_eq!(k.given(Setting::Instance, &Value::text("all")), "instance='all'");
        assert_eq!(k.given(Setting::Instance, &Value::Placeholder("N")), "instance=N");
        assert_eq!(k.value(&Value::text("auto")), "'auto'");
        assert_eq!(k.without(&[Setting::RateTerm]), "with rate_term=False");
        assert_eq!(
            k.without(&[Setting::Instance, Setting::DeviceId]),
            "without instance and device_id"
        );
        assert_eq!(
            k.fit_call(&Setting::FitFirmware.given(Value::text("px4"))),
            "`imutherm.tcal_fit(..., firmware='px4')`"
        );
        assert_eq!(k.name(Setting::TimeUnit), "the time unit");
        // As Python's repr("it's"), repr('a"b\'c') and repr("a\\b") write them.
        assert_eq!(python_str("it's"), r#""it's""#);
        assert_eq!(python_str("a\"b'c"), r#"'a"b\'c'"#);
        assert_eq!(python_str("a\\b"), r"'a\\b'");
    }
}
