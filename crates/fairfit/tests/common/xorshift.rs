//! A deterministic uniform and standard normal stream (xorshift64 and Box-Muller), for tests that
//! make large noisy clouds cheaply and with the same numbers on every platform.

/// The xorshift64 state (any non-zero seed).
pub struct Xorshift(pub u64);

impl Xorshift {
    /// A uniform number in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal number (Box-Muller on two uniforms).
    pub fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform(), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}
