//! Numbers as the page shows them: enough digits for a millimetre error to be read at a glance,
//! a dash for a value the run did not have.

use super::json_view::Stats;

/// The dash of a missing value.
pub const MISSING: &str = "–";

/// `v` with the decimals its size calls for: 0.097, 1.17, 26.5, 1234; 1.2e-5 for tiny values;
/// a dash when it is not finite.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return MISSING.into();
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if a >= 1000.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else if a >= 0.001 {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

/// [`num`] of an optional value.
pub fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| MISSING.into(), num)
}

/// `mean ± std (max M)`, what is recorded of it, or a dash when there was nothing to average.
pub fn stats(s: &Stats) -> String {
    let Some(mean) = s.mean else {
        return MISSING.into();
    };
    let mut t = num(mean);
    if let Some(std) = s.std {
        t += &format!(" ± {}", num(std));
    }
    if let Some(max) = s.max {
        t += &format!(" (max {})", num(max));
    }
    t
}

/// A fraction in [0, 1] as a percentage: 100 %, 7.2 %, 0.20 %.
pub fn percent(v: f64) -> String {
    if !v.is_finite() {
        return MISSING.into();
    }
    let p = v * 100.0;
    if p == 0.0 || p >= 10.0 {
        format!("{p:.0} %")
    } else if p >= 1.0 {
        format!("{p:.1} %")
    } else {
        format!("{p:.2} %")
    }
}

/// A setting as it was typed (10°, 0.15 ms): the shortest form when it has at most six
/// decimals, otherwise by [`num`] (a measured value such as a run time).
pub fn typed(f: f64) -> String {
    if f.is_finite() && ((f * 1e6).round() / 1e6 - f).abs() < 1e-12 {
        format!("{f}")
    } else {
        num(f)
    }
}

/// A JSON value of the run's settings as text: strings as they are, numbers by [`num`] when
/// they are not integers, arrays joined by commas (`none` when empty), null as a dash, objects
/// as `key: value` pairs.
pub fn setting(v: &serde_json::Value) -> String {
    use serde_json::Value;
    match v {
        Value::Null => MISSING.into(),
        Value::String(s) => s.clone(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => match n.as_i64() {
            Some(i) => i.to_string(),
            // Settings are shown as typed (0.15 ms, 45°); measured values (a run time) by num.
            None => n.as_f64().map_or_else(|| n.to_string(), typed),
        },
        Value::Array(items) if items.is_empty() => "none".into(),
        Value::Array(items) => items.iter().map(setting).collect::<Vec<_>>().join(", "),
        Value::Object(map) => map
            .iter()
            .map(|(k, v)| format!("{k}: {}", setting(v)))
            .collect::<Vec<_>>()
            .join("; "),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn numbers_by_size() {
        assert_eq!(num(0.0971979), "0.097");
        assert_eq!(num(1.1729), "1.17");
        assert_eq!(num(26.54), "26.5");
        assert_eq!(num(14845.0), "14845");
        assert_eq!(num(3.7e-5), "3.70e-5");
        assert_eq!(num(-0.25), "-0.250");
        assert_eq!(num(f64::NAN), MISSING);
        assert_eq!(opt(None), MISSING);
        assert_eq!(percent(0.0720588), "7.2 %");
        assert_eq!(
            (typed(10.0), typed(0.15), typed(783.640418732)),
            ("10".into(), "0.15".into(), "783.6".into())
        );
        assert_eq!(percent(1.0), "100 %");
        assert_eq!(percent(0.00198), "0.20 %");
    }

    #[test]
    fn statistics_and_settings() {
        let s = Stats {
            mean: Some(0.94),
            std: Some(0.28),
            max: Some(1.35),
            n: Some(12),
        };
        assert_eq!(stats(&s), "0.940 ± 0.280 (max 1.35)");
        assert_eq!(stats(&Stats::default()), MISSING);
        assert_eq!(setting(&json!([10.0, 40.0, 45])), "10, 40, 45");
        assert_eq!(setting(&json!(0.15)), "0.15");
        assert_eq!(setting(&json!(null)), MISSING);
        assert_eq!(setting(&json!({"a": 1, "b": null})), "a: 1; b: –");
        assert_eq!(setting(&json!([])), "none");
        assert_eq!(setting(&json!(5.507780636)), "5.51");
    }
}
