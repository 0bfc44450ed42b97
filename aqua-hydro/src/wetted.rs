//! Wetted fractions: of a triangle with linear submergence
//! (docs/theory/hydrodynamics.md#wetted-fraction-of-a-triangle), of a line with a circular section
//! (#wetted-fraction-of-a-line) and of a point body (#point-bodies); each with its derivatives
//! with respect to the nodal submergences ζ_j = η_j − z_j.

use std::f64::consts::PI;

/// Exact wet-area fraction φ of a triangle with nodal submergences ζ (linear in between) and
/// ∂φ/∂ζ_j.
pub fn triangle(z: [f64; 3]) -> (f64, [f64; 3]) {
    let wet = [z[0] > 0.0, z[1] > 0.0, z[2] > 0.0];
    let n_wet = wet.iter().filter(|w| **w).count();
    match n_wet {
        3 => (1.0, [0.0; 3]),
        0 => {
            if z.iter().all(|v| v.abs() < 1e-12) {
                (0.5, [0.0; 3])
            } else {
                (0.0, [0.0; 3])
            }
        }
        1 => {
            let w = wet.iter().position(|x| *x).unwrap_or(0);
            let (a, b) = ((w + 1) % 3, (w + 2) % 3);
            let (zw, za, zb) = (z[w], z[a], z[b]);
            let (p, q) = (zw - za, zw - zb);
            let phi = zw * zw / (p * q);
            let mut d = [0.0; 3];
            d[w] = 2.0 * zw / (p * q) - zw * zw * (p + q) / (p * p * q * q);
            d[a] = zw * zw / (p * p * q);
            d[b] = zw * zw / (p * q * q);
            (phi, d)
        }
        _ => {
            let dry = wet.iter().position(|x| !*x).unwrap_or(0);
            let (a, b) = ((dry + 1) % 3, (dry + 2) % 3);
            let (zd, za, zb) = (z[dry], z[a], z[b]);
            let (p, q) = (za - zd, zb - zd);
            let psi = zd * zd / (p * q);
            let mut d = [0.0; 3];
            d[dry] = -(2.0 * zd / (p * q) + zd * zd * (p + q) / (p * p * q * q));
            d[a] = zd * zd / (p * p * q);
            d[b] = zd * zd / (p * q * q);
            (1.0 - psi, d)
        }
    }
}

/// Submerged fraction ϕ of a circle of radius r whose centre is ζ below the surface, and
/// dϕ/dζ.
#[inline]
pub fn section(zeta: f64, r: f64) -> (f64, f64) {
    if zeta >= r {
        (1.0, 0.0)
    } else if zeta <= -r {
        (0.0, 0.0)
    } else {
        let u = (zeta / r).clamp(-1.0, 1.0);
        let beta = 2.0 * (-u).acos();
        (
            (beta - beta.sin()) / (2.0 * PI),
            2.0 / (PI * r) * (1.0 - u * u).max(0.0).sqrt(),
        )
    }
}

/// 4-point Gauss–Legendre nodes and weights on [−1, 1].
const GL_X: [f64; 4] = [
    -0.861_136_311_594_052_6,
    -0.339_981_043_584_856_3,
    0.339_981_043_584_856_3,
    0.861_136_311_594_052_6,
];
const GL_W: [f64; 4] = [
    0.347_854_845_137_453_9,
    0.652_145_154_862_546_1,
    0.652_145_154_862_546_1,
    0.347_854_845_137_453_9,
];

/// K = ∫_lo^hi ϕ(ζ) dζ (Gauss–Legendre on the part inside [−r, r], exact outside) and
/// ∂K/∂lo, ∂K/∂hi of that quadrature.
fn section_integral(lo: f64, hi: f64, r: f64) -> (f64, f64, f64) {
    let (mut k, mut dlo, mut dhi) = (0.0, 0.0, 0.0);
    // fully wet part [max(lo, r), hi]
    if hi > r {
        k += hi - lo.max(r);
        dhi += 1.0;
        if lo > r {
            dlo -= 1.0;
        }
    }
    // transition part [a, b] = [max(lo, −r), min(hi, r)]
    let (a, b) = (lo.max(-r), hi.min(r));
    if b > a {
        let (h, m) = (0.5 * (b - a), 0.5 * (a + b));
        let (mut sum, mut da, mut db) = (0.0, 0.0, 0.0);
        for g in 0..4 {
            let (p, dp) = section(m + h * GL_X[g], r);
            sum += GL_W[g] * p;
            da += GL_W[g] * dp * 0.5 * (1.0 - GL_X[g]);
            db += GL_W[g] * dp * 0.5 * (1.0 + GL_X[g]);
        }
        k += h * sum;
        if lo > -r {
            dlo += -0.5 * sum + h * da;
        }
        if hi < r {
            dhi += 0.5 * sum + h * db;
        }
    }
    (k, dlo, dhi)
}

/// Wetted fraction φ̄ = ∫₀¹ ϕ(ζ(ξ)) dξ of a line with circular section of radius r whose
/// centreline submergence varies linearly from ζ₁ to ζ₂, and ∂φ̄/∂ζ₁, ∂φ̄/∂ζ₂.
///
/// Computed as φ̄ = (1/(ζ₂ − ζ₁))·∫_{ζ₁}^{ζ₂} ϕ dζ with 4-point Gauss–Legendre on the part
/// where |ζ| < r (the sub-intervals of docs/theory/hydrodynamics.md#wetted-fraction-of-a-line
/// split at ζ = ±r, mapped affinely), so the derivatives are exact derivatives of the computed
/// φ̄.
pub fn line(z1: f64, z2: f64, r: f64) -> (f64, [f64; 2]) {
    if r <= 0.0 {
        return length_fraction(z1, z2);
    }
    let dz = z2 - z1;
    if dz.abs() <= 1e-7 * r {
        let (p, dp) = section(0.5 * (z1 + z2), r);
        return (p, [0.5 * dp, 0.5 * dp]);
    }
    let (lo, hi) = if dz > 0.0 { (z1, z2) } else { (z2, z1) };
    let len = hi - lo;
    let (k, dlo, dhi) = section_integral(lo, hi, r);
    let phi = k / len;
    let d_lo = (dlo + phi) / len;
    let d_hi = (dhi - phi) / len;
    if dz > 0.0 {
        (phi, [d_lo, d_hi])
    } else {
        (phi, [d_hi, d_lo])
    }
}

/// Wet length fraction of a line of zero thickness.
fn length_fraction(z1: f64, z2: f64) -> (f64, [f64; 2]) {
    match (z1 > 0.0, z2 > 0.0) {
        (true, true) => (1.0, [0.0; 2]),
        (false, false) => (0.0, [0.0; 2]),
        (true, false) => {
            let d = z1 - z2;
            (z1 / d, [-z2 / (d * d), z1 / (d * d)])
        }
        (false, true) => {
            let d = z2 - z1;
            (z2 / d, [z2 / (d * d), -z1 / (d * d)])
        }
    }
}

/// Point body fraction φ_p = clamp(ζ/h_p + ½, 0, 1) (a step at ζ = 0 if h_p = 0) and dφ_p/dζ.
pub fn point(zeta: f64, height: f64) -> (f64, f64) {
    if height <= 0.0 {
        return (
            if zeta > 0.0 {
                1.0
            } else if zeta == 0.0 {
                0.5
            } else {
                0.0
            },
            0.0,
        );
    }
    let f = zeta / height + 0.5;
    if f <= 0.0 {
        (0.0, 0.0)
    } else if f >= 1.0 {
        (1.0, 0.0)
    } else {
        (f, 1.0 / height)
    }
}

/// Submerged volume fraction of a sphere of radius r whose centre is ζ below the surface, and
/// its derivative: with h = clamp(ζ + r, 0, 2r) the depth of its lowest point, the cap
/// πh²(3r − h)/3 over 4πr³/3, i.e. h²(3r − h)/(4r³), and d/dζ = 3h(2r − h)/(4r³) (the
/// waterplane area π(2rh − h²) over the volume).
pub fn sphere(zeta: f64, r: f64) -> (f64, f64) {
    if r <= 0.0 {
        return point(zeta, 0.0);
    }
    let h = zeta + r;
    if h <= 0.0 {
        (0.0, 0.0)
    } else if h >= 2.0 * r {
        (1.0, 0.0)
    } else {
        let r3 = 4.0 * r * r * r;
        (h * h * (3.0 * r - h) / r3, 3.0 * h * (2.0 * r - h) / r3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn triangle_reference_values() {
        assert!((triangle([0.3, -0.1, -0.2]).0 - 0.45).abs() < 1e-15);
        assert!((triangle([0.3, 0.2, -0.2]).0 - 0.8).abs() < 1e-15);
        assert_eq!(triangle([0.0, 0.0, 0.0]).0, 0.5);
        assert_eq!(triangle([1.0, 2.0, 3.0]).0, 1.0);
        assert_eq!(triangle([-1.0, -2.0, 0.0]).0, 0.0);
    }

    #[test]
    fn horizontal_pipe_reference_values() {
        let r = 0.175;
        let (phi, _) = line(0.0, 0.0, r);
        assert!((phi - 0.5).abs() < 1e-15);
        let buoyancy = 1025.0 * 9.80665 * PI / 4.0 * 0.35 * 0.35 * phi;
        assert!((buoyancy - 483.549029).abs() < 5e-7, "{buoyancy}");
        let (phi, _) = line(r / 2.0, r / 2.0, r);
        assert!((phi - 0.8044988905).abs() < 5e-11);
    }

    /// ϕ·πR² is the circular segment A_sub(h) = R²·acos((R − h)/R) − (R − h)·√(2Rh − h²) of
    /// docs/theory/farm.md#partially-submerged-circular-sections (h = ζ + R, the depth of the
    /// lowest point), and dϕ/dζ·πR² is the wetted chord 2√(2Rh − h²); also for a horizontal
    /// line element.
    #[test]
    fn section_is_the_circular_segment_law() {
        let r = 0.175;
        for k in 0..=20 {
            let h = 2.0 * r * k as f64 / 20.0;
            let a_sub = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
            let chord = 2.0 * (2.0 * r * h - h * h).max(0.0).sqrt();
            let (phi, dphi) = section(h - r, r);
            let area = PI * r * r;
            assert!((phi * area - a_sub).abs() < 1e-15, "h = {h}: {phi}");
            assert!((dphi * area - chord).abs() < 1e-13, "h = {h}: {dphi}");
            let (phi_l, d) = line(h - r, h - r, r);
            assert!((phi_l - phi).abs() < 1e-15 && (d[0] + d[1] - dphi).abs() < 1e-13);
        }
    }

    #[test]
    fn line_derivatives_match_finite_differences() {
        let r = 0.2;
        for (z1, z2) in [
            (0.05, 0.05),
            (-0.1, 0.3),
            (0.15, -0.5),
            (0.5, 0.1),
            (-0.05, 0.12),
        ] {
            let (_, d) = line(z1, z2, r);
            let h = 1e-6;
            let fd1 = (line(z1 + h, z2, r).0 - line(z1 - h, z2, r).0) / (2.0 * h);
            let fd2 = (line(z1, z2 + h, r).0 - line(z1, z2 - h, r).0) / (2.0 * h);
            assert!(
                (fd1 - d[0]).abs() < 1e-7 * (1.0 + d[0].abs()),
                "{z1},{z2}: {} {fd1}",
                d[0]
            );
            assert!(
                (fd2 - d[1]).abs() < 1e-7 * (1.0 + d[1].abs()),
                "{z1},{z2}: {} {fd2}",
                d[1]
            );
        }
    }

    #[test]
    fn quadrature_is_accurate() {
        // exact ∫ϕ over the whole band is r (half the band is wet on average)
        let r = 0.3;
        let (phi, _) = line(-r, r, r);
        assert!((phi - 0.5).abs() < 1e-12);
        // against a fine midpoint rule
        let (z1, z2) = (-0.1, 0.25);
        let n = 200_000;
        let fine: f64 = (0..n)
            .map(|i| section(z1 + (i as f64 + 0.5) / n as f64 * (z2 - z1), r).0)
            .sum::<f64>()
            / n as f64;
        assert!((line(z1, z2, r).0 - fine).abs() < 1e-4);
    }

    #[test]
    fn thin_line_is_length_fraction() {
        let (phi, _) = line(0.3, -0.1, 1e-9);
        assert!((phi - 0.75).abs() < 1e-8);
        let (phi, _) = line(0.3, -0.1, 0.0);
        assert!((phi - 0.75).abs() < 1e-15);
    }

    #[test]
    fn point_fraction() {
        assert_eq!(point(0.1, 0.0).0, 1.0);
        assert_eq!(point(-0.1, 0.0).0, 0.0);
        assert_eq!(point(0.0, 2.0), (0.5, 0.5));
        assert_eq!(point(1.5, 2.0).0, 1.0);
    }

    #[test]
    fn sphere_fraction() {
        assert_eq!(sphere(0.0, 0.5), (0.5, 0.75 / 0.5));
        assert_eq!(sphere(-0.6, 0.5).0, 0.0);
        assert_eq!(sphere(0.6, 0.5).0, 1.0);
        // a cap of height r/2: πh²(3r − h)/3 / (4πr³/3) = (1/4)(5/2)/4 = 5/32
        assert!((sphere(-0.25, 0.5).0 - 5.0 / 32.0).abs() < 1e-15);
    }

    proptest! {
        #[test]
        fn triangle_fraction_bounded_and_continuous(
            a in -1.0f64..1.0, b in -1.0f64..1.0, c in -1.0f64..1.0, i in 0usize..3,
        ) {
            let z = [a, b, c];
            let (phi, d) = triangle(z);
            prop_assert!((0.0..=1.0).contains(&phi));
            // continuity: a small move of one node changes φ by at most ~|∂φ/∂ζ|·h
            let mut z2 = z;
            z2[i] += 1e-9;
            let (phi2, _) = triangle(z2);
            prop_assert!((phi2 - phi).abs() < 1e-9 * (d[i].abs() + 1.0) * 10.0 + 1e-12 || (phi2 - phi).abs() < 1e-6);
            // exact area fraction against a fine sampling of the triangle
            let n = 200;
            let mut wet = 0usize;
            let mut tot = 0usize;
            for p in 0..n {
                for q in 0..(n - p) {
                    let (u, v) = ((p as f64 + 1.0 / 3.0) / n as f64, (q as f64 + 1.0 / 3.0) / n as f64);
                    let zz = a * (1.0 - u - v) + b * u + c * v;
                    tot += 1;
                    if zz > 0.0 { wet += 1; }
                }
            }
            prop_assert!((wet as f64 / tot as f64 - phi).abs() < 0.03);
        }

        #[test]
        fn line_fraction_bounded_monotone(z1 in -1.0f64..1.0, z2 in -1.0f64..1.0, r in 0.01f64..0.5) {
            let (phi, d) = line(z1, z2, r);
            prop_assert!((-1e-12..=1.0 + 1e-12).contains(&phi));
            prop_assert!(d[0] >= 0.0 && d[1] >= 0.0);
            let (phi_up, _) = line(z1 + 0.01, z2 + 0.01, r);
            prop_assert!(phi_up + 1e-9 >= phi);
        }
    }
}
