//! A 3-vector generic over [`Real`], so one integrator serves f32 and f64.

use crate::real::Real;
use std::ops::{Add, Div, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V3<T> {
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Real> V3<T> {
    #[inline(always)]
    pub fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }
    #[inline(always)]
    pub fn splat(v: T) -> Self {
        Self::new(v, v, v)
    }
    #[inline(always)]
    pub fn of(a: [f32; 3]) -> Self {
        Self::new(T::of(a[0]), T::of(a[1]), T::of(a[2]))
    }
    #[inline(always)]
    pub fn of64(a: glam::DVec3) -> Self {
        Self::new(T::of64(a.x), T::of64(a.y), T::of64(a.z))
    }
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }

    #[inline(always)]
    pub fn length_squared(self) -> T {
        self.dot(self)
    }
    #[inline(always)]
    pub fn length(self) -> T {
        self.length_squared().sqrt()
    }
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self / self.length()
    }
    #[inline(always)]
    pub fn mul_elem(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
    #[inline(always)]
    pub fn map(self, f: impl Fn(T) -> T) -> Self {
        Self::new(f(self.x), f(self.y), f(self.z))
    }
    #[inline(always)]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
    #[inline(always)]
    pub fn to_f64(self) -> [f64; 3] {
        [self.x.to_f64(), self.y.to_f64(), self.z.to_f64()]
    }
}

impl<T: Real> Add for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<T: Real> Sub for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<T: Real> Neg for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}
impl<T: Real> Mul<T> for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}
impl<T: Real> Div<T> for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: T) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }
}
