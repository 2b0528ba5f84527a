//! `windrive bench rainflow`: rainflow counting plus DELs (m = 3, 6, 9 at 1 Hz over a 1 s sample
//! spacing) of a long series in one pass, best of three; the counts and sums are checksums that
//! benches/rainflow.py compares with the Python packages on the same series.

use crate::analysis::fatigue::damage::DamageSums;
use crate::analysis::fatigue::rainflow;
use std::path::Path;

/// A series stored as raw little-endian f64 (benches/rainflow.py writes it).
pub fn read_series(path: &Path) -> std::io::Result<Vec<f64>> {
    Ok(std::fs::read(path)?
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect())
}

/// A seeded random walk of `samples` points: reproducible without a dependency (xorshift).
pub fn random_walk(samples: usize) -> Vec<f64> {
    let mut random = crate::xorshift::Xorshift::new(0x9e37_79b9_7f4a_7c15);
    let mut walk = 0.0;
    (0..samples)
        .map(|_| {
            walk += random.unit() - 0.5;
            walk
        })
        .collect()
}

/// The timing and the checksums of one series.
pub struct Counted {
    /// Best of three, counting and DELs only, s.
    pub seconds: f64,
    pub cycles: usize,
    /// Σ count · range and Σ count over the cycles.
    pub sum_count_range: f64,
    pub sum_count: f64,
    /// DELs at m = 3, 6, 9.
    pub dels: Vec<f64>,
}

impl Counted {
    /// The line `windrive bench rainflow` prints for a series of `samples` points (benches/rainflow.py
    /// reads it).
    pub fn to_json(&self, samples: usize) -> serde_json::Value {
        let dels = &self.dels;
        serde_json::json!({"samples": samples, "seconds": self.seconds, "cycles": self.cycles,
            "sum_count_range": self.sum_count_range, "sum_count": self.sum_count,
            "del": {"3": dels[0], "6": dels[1], "9": dels[2]}})
    }
}

pub fn run(x: &[f64]) -> Counted {
    let mut best = f64::MAX;
    let mut result = (0usize, 0.0, 0.0, Vec::new());
    for _ in 0..3 {
        let started = std::time::Instant::now();
        let mut n = 0usize;
        let (mut total, mut count) = (0.0, 0.0);
        // DELs accumulated while counting: one pass, no cycle list
        let mut sums = DamageSums::new(&[3.0, 6.0, 9.0]);
        let mut counter = rainflow::Counter::new();
        let mut add = |c: rainflow::Cycle| {
            n += 1;
            total += c.count * c.range;
            count += c.count;
            sums.add(&c);
        };
        counter.extend(x, &mut add);
        counter.finish(&mut add);
        let dels = sums.dels((x.len().max(2) - 1) as f64);
        best = best.min(started.elapsed().as_secs_f64());
        result = (n, total, count, dels);
    }
    let (cycles, sum_count_range, sum_count, dels) = result;
    Counted {
        seconds: best,
        cycles,
        sum_count_range,
        sum_count,
        dels,
    }
}
