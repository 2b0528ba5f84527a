//! Seeded pseudo-random numbers without a dependency (Marsaglia's xorshift64, shifts 13, 7, 17):
//! the reproducible random states the unit tests draw and the series the benchmarks count.

/// The generator's state; a nonzero seed gives a sequence of period 2⁶⁴ − 1.
#[derive(Debug, Clone)]
pub struct Xorshift(u64);

impl Xorshift {
    pub fn new(seed: u64) -> Self {
        assert_ne!(seed, 0, "xorshift needs a nonzero seed");
        Xorshift(seed)
    }

    /// The next state.
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.0;
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        *s
    }

    /// Uniform on [0, 1), from the state's top 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform on [−1, 1).
    pub fn symmetric(&mut self) -> f64 {
        self.unit() * 2.0 - 1.0
    }
}
