//! Forward-mode dual numbers (value + one derivative): they differentiate the contact
//! element's stiffness with respect to the contact position exactly, without hand-written quotients.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A number `re + eps * du` with `eps^2 = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    /// Value.
    pub re: f64,
    /// Derivative with respect to the seeded variable.
    pub du: f64,
}

impl Dual {
    /// A constant (zero derivative).
    pub fn cst(re: f64) -> Self {
        Dual { re, du: 0.0 }
    }
}

impl From<f64> for Dual {
    fn from(v: f64) -> Self {
        Dual::cst(v)
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            re: self.re + o.re,
            du: self.du + o.du,
        }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            re: self.re - o.re,
            du: self.du - o.du,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            re: self.re * o.re,
            du: self.du * o.re + self.re * o.du,
        }
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual {
            re: self.re / o.re,
            du: (self.du * o.re - self.re * o.du) / (o.re * o.re),
        }
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            re: -self.re,
            du: -self.du,
        }
    }
}

/// Arithmetic the flexibility integrals need; implemented by `f64` and `Dual`.
pub trait Real:
    Copy + From<f64> + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
}
impl Real for f64 {}
impl Real for Dual {}
