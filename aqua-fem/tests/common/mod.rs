//! Shared test/bench helpers: line builder, catenary oracles, a simple water-load provider.
#![allow(dead_code)]

use aqua_fem::*;

/// Adds a line of `n` segments from `a` to `b` with total unstretched length `l0`; the
/// as-built shape is the chord sagged by a parabola of depth `sag` (downwards). Returns nodes.
pub fn add_line(
    b: &mut ModelBuilder,
    a: [f64; 3],
    end: [f64; 3],
    n: usize,
    l0: f64,
    group: GroupId,
    sag: f64,
) -> Vec<usize> {
    // Points equally spaced in arc length along the sagged chord (like a line builder).
    let shape = |s: f64| {
        [
            a[0] + s * (end[0] - a[0]),
            a[1] + s * (end[1] - a[1]),
            a[2] + s * (end[2] - a[2]) - 4.0 * sag * s * (1.0 - s),
        ]
    };
    let fine = 64 * n;
    let mut arc = vec![0.0; fine + 1];
    for i in 1..=fine {
        let (p, q) = (
            shape((i - 1) as f64 / fine as f64),
            shape(i as f64 / fine as f64),
        );
        arc[i] = arc[i - 1]
            + ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)).sqrt();
    }
    let mut nodes = Vec::with_capacity(n + 1);
    let mut j = 0;
    for i in 0..=n {
        let target = arc[fine] * i as f64 / n as f64;
        while j < fine && arc[j + 1] < target {
            j += 1;
        }
        let s = if i == n {
            1.0
        } else {
            let f = (target - arc[j]) / (arc[j + 1] - arc[j]).max(1e-300);
            (j as f64 + f.clamp(0.0, 1.0)) / fine as f64
        };
        nodes.push(b.add_node(shape(s)).unwrap());
    }
    for i in 0..n {
        b.add_cable(
            nodes[i],
            nodes[i + 1],
            group,
            UnstretchedLength::Given(l0 / n as f64),
        )
        .unwrap();
    }
    nodes
}

/// Adds a line of `n` equal segments along the polyline `pts` (total unstretched length =
/// the polyline length, so the as-built state is unstrained). Returns the nodes.
pub fn add_polyline(
    b: &mut ModelBuilder,
    pts: &[[f64; 3]],
    n: usize,
    group: GroupId,
) -> Vec<usize> {
    let seg: Vec<f64> = pts
        .windows(2)
        .map(|w| {
            ((w[1][0] - w[0][0]).powi(2)
                + (w[1][1] - w[0][1]).powi(2)
                + (w[1][2] - w[0][2]).powi(2))
            .sqrt()
        })
        .collect();
    let total: f64 = seg.iter().sum();
    let mut nodes = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let mut d = total * i as f64 / n as f64;
        let mut k = 0;
        while k + 1 < seg.len() && d > seg[k] {
            d -= seg[k];
            k += 1;
        }
        let f = (d / seg[k]).clamp(0.0, 1.0);
        let p = [0, 1, 2].map(|c| pts[k][c] + f * (pts[k + 1][c] - pts[k][c]));
        nodes.push(b.add_node(p).unwrap());
    }
    for i in 0..n {
        b.add_cable(
            nodes[i],
            nodes[i + 1],
            group,
            UnstretchedLength::Given(total / n as f64),
        )
        .unwrap();
    }
    nodes
}

/// Level elastic catenary (Irvine): returns (H, end tension, sag) for span l, length L0,
/// weight w per unstretched metre, EA.
pub fn level_catenary(l: f64, l0: f64, w: f64, ea: f64) -> (f64, f64, f64) {
    let f = |h: f64| h * l0 / ea + 2.0 * h / w * (w * l0 / (2.0 * h)).asinh() - l;
    let (mut lo, mut hi) = (1e-6, 1e9);
    for _ in 0..300 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let h = 0.5 * (lo + hi);
    let v = 0.5 * w * l0;
    let t = (h * h + v * v).sqrt();
    let sag = w * l0 * l0 / (8.0 * ea) + ((h * h + v * v).sqrt() - h) / w;
    (h, t, sag)
}

/// Touchdown catenary on a frictionless seabed: returns (H, V_B) for horizontal distance l
/// and height h of the fairlead above the anchor on the seabed.
pub fn touchdown(l: f64, h: f64, l0: f64, w: f64, ea: f64) -> (f64, f64) {
    let res = |hh: f64, vb: f64| -> [f64; 2] {
        let lb = l0 - vb / w;
        [
            lb + hh / w * (vb / hh).asinh() + hh * l0 / ea - l,
            hh / w * ((1.0 + (vb / hh).powi(2)).sqrt() - 1.0) + vb * vb / (2.0 * ea * w) - h,
        ]
    };
    let (mut hh, mut vb) = (0.2 * w * h, 0.9 * w * h);
    for _ in 0..200 {
        let r = res(hh, vb);
        let eps = 1e-7;
        let rh = res(hh * (1.0 + eps), vb);
        let rv = res(hh, vb * (1.0 + eps));
        let j = [
            [(rh[0] - r[0]) / (hh * eps), (rv[0] - r[0]) / (vb * eps)],
            [(rh[1] - r[1]) / (hh * eps), (rv[1] - r[1]) / (vb * eps)],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let dh = (r[0] * j[1][1] - r[1] * j[0][1]) / det;
        let dv = (j[0][0] * r[1] - j[1][0] * r[0]) / det;
        let lam = 1.0f64
            .min(0.5 * hh / dh.abs().max(1e-300))
            .min(0.5 * vb / dv.abs().max(1e-300));
        hh -= lam * dh;
        vb -= lam * dv;
        if dh.abs() < 1e-12 * hh && dv.abs() < 1e-12 * vb {
            break;
        }
    }
    (hh, vb)
}

/// Buoyancy of fully submerged line elements plus Morison normal drag ½ρC_n·d·l|w|w with
/// w = P(u − v̄), in a uniform current u. ∂f/∂v is analytic when `analytic`, otherwise left to
/// the solver's finite differences; ∂f/∂x is always left to the solver.
#[derive(Debug, Clone)]
pub struct WaterLines {
    pub nodes: Vec<[usize; 2]>,
    pub l0: Vec<f64>,
    pub area: f64,
    pub diameter: f64,
    pub cd: f64,
    pub rho: f64,
    pub g: f64,
    pub current: [f64; 3],
    pub analytic: bool,
}

impl WaterLines {
    pub fn new(model: &Model, diameter: f64, cd: f64, current: [f64; 3]) -> Self {
        let env = model.environment();
        Self {
            nodes: model.elements().iter().map(|e| [e.a, e.b]).collect(),
            l0: model.elements().iter().map(|e| e.l0).collect(),
            area: std::f64::consts::PI / 4.0 * diameter * diameter,
            diameter,
            cd,
            rho: env.water_density,
            g: env.gravity,
            current,
            analytic: true,
        }
    }
}

impl LoadProvider for WaterLines {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    fn element_nodes(&self, e: usize) -> &[usize] {
        &self.nodes[e]
    }
    fn element_load(
        &self,
        e: usize,
        _t: f64,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        out: &mut ElementLoad,
    ) -> std::result::Result<(), LoadError> {
        let d = [x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2]];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if l <= 0.0 {
            return Err(LoadError::msg("zero-length line"));
        }
        let u = [d[0] / l, d[1] / l, d[2] / l];
        if 0.5 * (x[0][2] + x[1][2]) < 0.0 {
            let fb = 0.5 * self.rho * self.g * self.area * self.l0[e];
            out.force[0][2] += fb;
            out.force[1][2] += fb;
        }
        let mut rel = [0.0; 3];
        for k in 0..3 {
            rel[k] = self.current[k] - 0.5 * (v[0][k] + v[1][k]);
        }
        let ed = u[0] * rel[0] + u[1] * rel[1] + u[2] * rel[2];
        let w = [rel[0] - ed * u[0], rel[1] - ed * u[1], rel[2] - ed * u[2]];
        let s = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        let k = 0.5 * self.rho * self.cd * self.diameter * l;
        for j in 0..2 {
            for c in 0..3 {
                out.force[j][c] += 0.5 * k * s * w[c];
            }
        }
        if want.dfdv && self.analytic {
            // ∂f/∂v̄ = −k|w|(P + ŵŵᵀ); equal shares → ¼ per node pair.
            for r in 0..3 {
                for c in 0..3 {
                    let p = if r == c { 1.0 } else { 0.0 } - u[r] * u[c];
                    let ww = if s > 1e-12 { w[r] * w[c] / s } else { 0.0 };
                    let val = -0.25 * k * (s * p + ww);
                    for i in 0..2 {
                        for j in 0..2 {
                            out.dfdv[3 * i + r][3 * j + c] = val;
                        }
                    }
                }
            }
            out.has_dfdv = true;
        }
        Ok(())
    }
}
