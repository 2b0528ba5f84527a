//! A scene's quantities of interest: the few numbers a drivetrain engineer reads off a run (HSS torque
//! peak and RMS, DEL of the shafts, the largest mesh force, the dominant frequency while braking),
//! each with the relative error it may carry. A run's error is the relative error of each quantity
//! against a reference run; `windrive chart work-precision` and `windrive fidelity` rank methods
//! and models by it.
//!
//! They are declared in a side file beside the scene, `quantities.toml`:
//!
//! ```toml
//! [[quantity]]
//! name = "HSS torque peak"
//! channel = "torsional.hss_torque"   # component.variable, as recorded
//! measure = "peak"                   # peak | rms | max | min | range | del | dominant-frequency
//! tolerance = 0.02                   # relative error the scene accepts
//! window = [5.0, 30.0]               # optional: seconds the measure reads
//! # m = 6                            # del: S-N slope (equivalent cycles: 1 per second)
//! # f_min = 0.3                      # dominant-frequency: lowest frequency considered, Hz
//! ```

use crate::analysis::fatigue::damage::DamageSums;
use crate::analysis::fatigue::rainflow::Counter;
use crate::analysis::signal::metrics;
use crate::analysis::signal::spectrum::dominant_in_window;
use serde::Deserialize;
use std::path::Path;

/// File name of the side file in a scene folder.
pub const FILE_NAME: &str = "quantities.toml";

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Measure {
    /// Largest magnitude.
    Peak,
    Rms,
    Max,
    Min,
    /// Largest minus smallest value.
    Range,
    /// Damage-equivalent load for slope `m`, one equivalent cycle per second.
    Del,
    /// Frequency of the largest spectral peak above `f_min`.
    DominantFrequency,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    pub name: String,
    pub channel: String,
    pub measure: Measure,
    pub tolerance: f64,
    pub window: Option<[f64; 2]>,
    pub m: Option<f64>,
    pub f_min: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    quantity: Vec<Quantity>,
}

/// Reads and checks a quantities file; errors name the file and, where the parser knows it, the
/// line and key.
pub fn load(path: &Path) -> Result<Vec<Quantity>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

pub fn parse(text: &str) -> Result<Vec<Quantity>, String> {
    let file: File = toml::from_str(text).map_err(|e| e.to_string().trim_end().to_string())?;
    if file.quantity.is_empty() {
        return Err("no [[quantity]] declared".into());
    }
    for q in &file.quantity {
        let fail = |what: &str| Err(format!("quantity {:?}: {what}", q.name));
        if !(q.tolerance > 0.0 && q.tolerance.is_finite()) {
            return fail("tolerance must be a positive relative error, e.g. 0.02");
        }
        if !q.channel.contains('.') {
            return fail("channel must be component.variable, e.g. torsional.hss_torque");
        }
        if let Some([a, b]) = q.window
            && !(a.is_finite() && b.is_finite() && a < b)
        {
            return fail("window must be [start, end] seconds with start < end");
        }
        match (q.measure, q.m) {
            (Measure::Del, Some(m)) if m > 0.0 && m.is_finite() => {}
            (Measure::Del, _) => return fail("measure del needs the S-N slope m > 0, e.g. m = 6"),
            (_, Some(_)) => return fail("m applies to measure del only"),
            _ => {}
        }
        if q.f_min.is_some() && q.measure != Measure::DominantFrequency {
            return fail("f_min applies to measure dominant-frequency only");
        }
    }
    Ok(file.quantity)
}

impl Quantity {
    /// The quantity over a series sampled at times `t`, or an error naming what is missing (a
    /// window with too few samples for a spectrum).
    pub fn evaluate(&self, t: &[f64], x: &[f64]) -> Result<f64, String> {
        let (from, to) = match self.window {
            Some([a, b]) => (a, b),
            None => (f64::NEG_INFINITY, f64::INFINITY),
        };
        let i0 = t.partition_point(|&v| v < from);
        let i1 = t.partition_point(|&v| v <= to);
        let s = &x[i0..i1.max(i0)];
        if s.is_empty() {
            return Err(format!("{}: no sample in the window", self.name));
        }
        let value = match self.measure {
            Measure::Peak => metrics::peak(s),
            Measure::Rms => metrics::rms(s),
            Measure::Max => s.iter().cloned().fold(f64::MIN, f64::max),
            Measure::Min => s.iter().cloned().fold(f64::MAX, f64::min),
            Measure::Range => metrics::range(s),
            Measure::Del => {
                let m = self.m.unwrap_or(6.0);
                let mut sums = DamageSums::new(&[m]);
                let mut counter = Counter::new();
                counter.extend(s, &mut |c| sums.add(&c));
                counter.finish(&mut |c| sums.add(&c));
                let seconds = t[i1 - 1] - t[i0];
                sums.dels(seconds.max(f64::MIN_POSITIVE))[0]
            }
            Measure::DominantFrequency => {
                let (a, b) = (t[i0], t[i1 - 1] + (t[1] - t[0]));
                dominant_in_window(t, x, a, b, self.f_min.unwrap_or(0.0))
                    .map(|(f, _, _)| f)
                    .ok_or_else(|| format!("{}: the window holds too few samples for a spectrum", self.name))?
            }
        };
        Ok(value)
    }
}

/// Relative error of `value` against `reference` (absolute where the reference is zero).
pub fn relative_error(value: f64, reference: f64) -> f64 {
    let d = (value - reference).abs();
    if reference == 0.0 { d } else { d / reference.abs() }
}

/// The distinct channels the quantities read, in first-use order.
pub fn channels(quantities: &[Quantity]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for q in quantities {
        if !out.contains(&q.channel) {
            out.push(q.channel.clone());
        }
    }
    out
}

/// Every quantity of a run recorded as `columns` (time first, then `channels` in order).
pub fn evaluate_all(quantities: &[Quantity], channels: &[String], columns: &[Vec<f64>]) -> Result<Vec<f64>, String> {
    quantities
        .iter()
        .map(|q| {
            let k = channels
                .iter()
                .position(|c| *c == q.channel)
                .ok_or_else(|| format!("{}: channel {} not recorded", q.name, q.channel))?;
            q.evaluate(&columns[0], &columns[k + 1])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"
[[quantity]]
name = "peak"
channel = "a.x"
measure = "peak"
tolerance = 0.01

[[quantity]]
name = "del"
channel = "a.x"
measure = "del"
m = 4
tolerance = 0.05

[[quantity]]
name = "f"
channel = "a.x"
measure = "dominant-frequency"
f_min = 0.5
window = [1.0, 9.0]
tolerance = 0.01
"#;

    /// A 3 Hz sine of amplitude 2 over 10 s sampled at 1 kHz: peak 2, dominant frequency 3 Hz, and
    /// the DEL at m = 4 with one equivalent cycle per second: starting and ending at zero, rainflow
    /// counts 29.5 cycles of range 4 and two half cycles of range 2 (the start and the end), so
    /// DEL = 4·((29.5 + 2·0.5·(2/4)⁴) / 9.999)^(1/4).
    #[test]
    fn measures_of_a_sine() {
        let q = parse(EXAMPLE).unwrap();
        let t: Vec<f64> = (0..10_000).map(|k| k as f64 * 1e-3).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|t| 2.0 * (std::f64::consts::TAU * 3.0 * t).sin())
            .collect();
        let v = evaluate_all(&q, &["a.x".into()], &[t, x]).unwrap();
        assert!((v[0] - 2.0).abs() < 1e-4, "{}", v[0]);
        let del = 4.0 * ((29.5 + 0.0625) / 9.999f64).powf(0.25);
        assert!(relative_error(v[1], del) < 1e-4, "{} vs {del}", v[1]);
        assert!((v[2] - 3.0).abs() < 0.01, "{}", v[2]);
    }

    #[test]
    fn mistakes_are_named() {
        let bad = EXAMPLE.replace("m = 4\n", "");
        assert!(parse(&bad).unwrap_err().contains("needs the S-N slope"));
        let bad = EXAMPLE.replace(
            "tolerance = 0.01\n\n[[quantity]]\nname = \"del\"",
            "tolerance = -1\n\n[[quantity]]\nname = \"del\"",
        );
        assert!(parse(&bad).unwrap_err().contains("tolerance"));
        let bad = EXAMPLE.replace("measure = \"peak\"", "measure = \"mean\"");
        let e = parse(&bad).unwrap_err();
        assert!(e.contains("line") && e.contains("mean"), "{e}");
        assert!(
            parse(&EXAMPLE.replace("a.x", "ax"))
                .unwrap_err()
                .contains("component.variable")
        );
    }
}
