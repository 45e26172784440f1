//! The scalar the CPU reference computes in: f32 (`--method cpu`, the GPU's arithmetic) or f64
//! (`--method cpu-f64`, the accuracy ground truth).

use num_traits::{Float, FloatConst};

pub trait Real: Float + FloatConst + Send + Sync + std::fmt::Debug + 'static {
    fn of(x: f32) -> Self;
    fn of64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    /// The next representable value towards +∞ (towards −∞: `next_down`).
    fn next_up(self) -> Self;
    fn next_down(self) -> Self;
    /// Half the machine epsilon: the relative error bound of one rounding.
    fn unit_roundoff() -> Self;
}

impl Real for f32 {
    #[inline(always)]
    fn next_up(self) -> Self {
        f32::next_up(self)
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        f32::next_down(self)
    }
    #[inline(always)]
    fn unit_roundoff() -> Self {
        f32::EPSILON / 2.0
    }
    #[inline(always)]
    fn of(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn of64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    #[inline(always)]
    fn next_up(self) -> Self {
        f64::next_up(self)
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        f64::next_down(self)
    }
    #[inline(always)]
    fn unit_roundoff() -> Self {
        f64::EPSILON / 2.0
    }
    #[inline(always)]
    fn of(x: f32) -> Self {
        x as f64
    }
    #[inline(always)]
    fn of64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
}
