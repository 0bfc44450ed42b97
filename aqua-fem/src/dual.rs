//! Forward-mode automatic differentiation with dual numbers of fixed size: the value of a
//! function together with its gradient ([`Dual1`]) or its gradient and Hessian ([`Dual2`])
//! with respect to N variables, exact to round-off (docs/theory/fem.md#rod).
//!
//! For a unary function f of a dual number (v, g, H): (f(v), f'(v)·g, f'(v)·H + f''(v)·g gᵀ);
//! for a product: (uv, u·g_v + v·g_u, u·H_v + v·H_u + g_u g_vᵀ + g_v g_uᵀ). The arrays are
//! plain and of fixed size, so the loops vectorise and nothing is allocated.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic the rod's kinematics needs, on plain numbers and on dual numbers.
pub(crate) trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    /// A constant.
    fn cst(v: f64) -> Self;
    /// The value (without derivatives).
    fn val(self) -> f64;
    fn sqrt(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    /// atan2(self, x).
    fn atan2(self, x: Self) -> Self;
}

impl Real for f64 {
    fn cst(v: f64) -> Self {
        v
    }
    fn val(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// Value and gradient with respect to N variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dual1<const N: usize> {
    pub v: f64,
    pub g: [f64; N],
}

/// Value, gradient and Hessian with respect to N variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dual2<const N: usize> {
    pub v: f64,
    pub g: [f64; N],
    pub h: [[f64; N]; N],
}

impl<const N: usize> Dual1<N> {
    /// Variable i of value v.
    pub fn var(v: f64, i: usize) -> Self {
        let mut g = [0.0; N];
        g[i] = 1.0;
        Self { v, g }
    }
    fn chain(self, f: f64, f1: f64) -> Self {
        Self {
            v: f,
            g: self.g.map(|c| f1 * c),
        }
    }
}

impl<const N: usize> Dual2<N> {
    /// Variable i of value v.
    pub fn var(v: f64, i: usize) -> Self {
        let mut g = [0.0; N];
        g[i] = 1.0;
        Self {
            v,
            g,
            h: [[0.0; N]; N],
        }
    }
    /// f(self) given f, f' and f'' at the value.
    fn chain(self, f: f64, f1: f64, f2: f64) -> Self {
        let mut h = self.h;
        for i in 0..N {
            for j in 0..N {
                h[i][j] = f1 * h[i][j] + f2 * self.g[i] * self.g[j];
            }
        }
        Self {
            v: f,
            g: self.g.map(|c| f1 * c),
            h,
        }
    }
}

macro_rules! common_ops {
    ($t:ident) => {
        impl<const N: usize> Add for $t<N> {
            type Output = Self;
            fn add(mut self, o: Self) -> Self {
                self.v += o.v;
                for i in 0..N {
                    self.g[i] += o.g[i];
                }
                self.add_h(&o, 1.0);
                self
            }
        }
        impl<const N: usize> Sub for $t<N> {
            type Output = Self;
            fn sub(mut self, o: Self) -> Self {
                self.v -= o.v;
                for i in 0..N {
                    self.g[i] -= o.g[i];
                }
                self.add_h(&o, -1.0);
                self
            }
        }
        impl<const N: usize> Neg for $t<N> {
            type Output = Self;
            fn neg(self) -> Self {
                self * -1.0
            }
        }
        impl<const N: usize> Add<f64> for $t<N> {
            type Output = Self;
            fn add(mut self, c: f64) -> Self {
                self.v += c;
                self
            }
        }
        impl<const N: usize> Div for $t<N> {
            type Output = Self;
            fn div(self, o: Self) -> Self {
                let r = 1.0 / o.v;
                self * o.recip_with(r)
            }
        }
    };
}

common_ops!(Dual1);
common_ops!(Dual2);

impl<const N: usize> Dual1<N> {
    fn add_h(&mut self, _o: &Self, _s: f64) {}
    fn recip_with(self, r: f64) -> Self {
        self.chain(r, -r * r)
    }
}

impl<const N: usize> Dual2<N> {
    fn add_h(&mut self, o: &Self, s: f64) {
        for i in 0..N {
            for j in 0..N {
                self.h[i][j] += s * o.h[i][j];
            }
        }
    }
    fn recip_with(self, r: f64) -> Self {
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
}

impl<const N: usize> Mul<f64> for Dual1<N> {
    type Output = Self;
    fn mul(self, c: f64) -> Self {
        Self {
            v: self.v * c,
            g: self.g.map(|x| x * c),
        }
    }
}

impl<const N: usize> Mul<f64> for Dual2<N> {
    type Output = Self;
    fn mul(self, c: f64) -> Self {
        Self {
            v: self.v * c,
            g: self.g.map(|x| x * c),
            h: self.h.map(|r| r.map(|x| x * c)),
        }
    }
}

impl<const N: usize> Mul for Dual1<N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut g = [0.0; N];
        for i in 0..N {
            g[i] = self.v * o.g[i] + o.v * self.g[i];
        }
        Self { v: self.v * o.v, g }
    }
}

impl<const N: usize> Mul for Dual2<N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut g = [0.0; N];
        let mut h = [[0.0; N]; N];
        for i in 0..N {
            g[i] = self.v * o.g[i] + o.v * self.g[i];
            for j in 0..N {
                h[i][j] = self.v * o.h[i][j]
                    + o.v * self.h[i][j]
                    + self.g[i] * o.g[j]
                    + o.g[i] * self.g[j];
            }
        }
        Self {
            v: self.v * o.v,
            g,
            h,
        }
    }
}

impl<const N: usize> Real for Dual1<N> {
    fn cst(v: f64) -> Self {
        Self { v, g: [0.0; N] }
    }
    fn val(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn atan2(self, x: Self) -> Self {
        // dθ = (x·dy − y·dx)/(x² + y²).
        let r = 1.0 / (x.v * x.v + self.v * self.v);
        let mut g = [0.0; N];
        for i in 0..N {
            g[i] = r * (x.v * self.g[i] - self.v * x.g[i]);
        }
        Self {
            v: self.v.atan2(x.v),
            g,
        }
    }
}

impl<const N: usize> Real for Dual2<N> {
    fn cst(v: f64) -> Self {
        Self {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }
    fn val(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }
    fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }
    fn atan2(self, x: Self) -> Self {
        // θ = atan2(y, x): g = n/r with n = x·g_y − y·g_x, r = x² + y²;
        // H = (∇n)/r − n ∇rᵀ/r², ∇n = g_x g_yᵀ + x·H_y − g_y g_xᵀ − y·H_x (as ∂n_i/∂j),
        // ∇r = 2(x·g_x + y·g_y); symmetric.
        let y = self;
        let r = x.v * x.v + y.v * y.v;
        let ri = 1.0 / r;
        let mut n = [0.0; N];
        let mut dr = [0.0; N];
        for i in 0..N {
            n[i] = x.v * y.g[i] - y.v * x.g[i];
            dr[i] = 2.0 * (x.v * x.g[i] + y.v * y.g[i]);
        }
        let mut h = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                let dn = x.g[j] * y.g[i] + x.v * y.h[i][j] - y.g[j] * x.g[i] - y.v * x.h[i][j];
                h[i][j] = ri * dn - ri * ri * n[i] * dr[j];
            }
        }
        for i in 0..N {
            for j in 0..i {
                let s = 0.5 * (h[i][j] + h[j][i]);
                h[i][j] = s;
                h[j][i] = s;
            }
        }
        Self {
            v: y.v.atan2(x.v),
            g: n.map(|c| ri * c),
            h,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(a, b) = atan2(a·b, sqrt(a) + cos(b)) / (1 + sin(a·a)) − b·b: every operation, against
    /// the closed-form derivatives by central differences.
    fn f<T: Real>(a: T, b: T) -> T {
        (a * b).atan2(a.sqrt() + b.cos()) / (T::cst(1.0) + (a * a).sin()) - b * b * 0.5 + a * 3.0
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        let (a, b) = (0.7, -1.3);
        let d = f(Dual2::<2>::var(a, 0), Dual2::<2>::var(b, 1));
        let d1 = f(Dual1::<2>::var(a, 0), Dual1::<2>::var(b, 1));
        let e = 1e-5;
        let fx = |a: f64, b: f64| f(a, b);
        assert!((d.v - fx(a, b)).abs() < 1e-15);
        let ga = (fx(a + e, b) - fx(a - e, b)) / (2.0 * e);
        let gb = (fx(a, b + e) - fx(a, b - e)) / (2.0 * e);
        for (got, want) in [(d.g[0], ga), (d.g[1], gb), (d1.g[0], ga), (d1.g[1], gb)] {
            assert!((got - want).abs() < 1e-8, "{got} vs {want}");
        }
        let haa = (fx(a + e, b) - 2.0 * fx(a, b) + fx(a - e, b)) / (e * e);
        let hbb = (fx(a, b + e) - 2.0 * fx(a, b) + fx(a, b - e)) / (e * e);
        let hab = (fx(a + e, b + e) - fx(a + e, b - e) - fx(a - e, b + e) + fx(a - e, b - e))
            / (4.0 * e * e);
        for (got, want) in [
            (d.h[0][0], haa),
            (d.h[1][1], hbb),
            (d.h[0][1], hab),
            (d.h[1][0], hab),
        ] {
            assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        }
    }
}
