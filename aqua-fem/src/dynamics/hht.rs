//! The HHT-α scheme (docs/theory/fem.md#hht-alpha): Newmark kinematics with
//! β = (1 + α)²/4, γ = ½ + α, the residual M·a_{n+1} + (1 − α)·q_{n+1} + α·q_n = 0 and the
//! Jacobian M/(βΔt²) + (1 − α)·[K + γ/(βΔt)·C]; the elastic force of cables and net twines
//! in it is the energy-consistent step force G_{n+1}, whose γ-weighted pair with G_n is the
//! discrete gradient of the member's energy plus HHT-α's own dissipative term
//! (docs/theory/fem.md#energy-consistent-hht-alpha).

use super::scheme::Nodal;
use crate::cable::{self, CableEval};
use crate::error::Result;
use crate::loads::LoadProvider;
use crate::model::{Cable, Model};
use crate::system::{Coef, EvalOptions, System, norm, sub};

/// HHT-α with line relaxation: a step in which one line's relaxation took more local
/// iterations than this while an element of it that was slack ended taut (a tightening front
/// crossing about as many elements) is halved (docs/theory/fem.md#line-relaxation-hht).
pub(crate) const HHT_FRONT_ELEMENTS: usize = 10;

/// HHT-α's parameters and the members' memory of its energy-consistent elastic force.
#[derive(Debug, Clone)]
pub(crate) struct Hht {
    /// α ∈ [0, 1/3].
    pub alpha: f64,
    /// β = (1 + α)²/4.
    pub beta: f64,
    /// γ = ½ + α.
    pub gamma: f64,
    /// The members' memory, lent to the system while it evaluates a step.
    forces: Option<HhtForces>,
}

impl Hht {
    pub(crate) fn new(alpha: f64) -> Self {
        Self {
            alpha,
            beta: 0.25 * (1.0 + alpha) * (1.0 + alpha),
            gamma: 0.5 + alpha,
            forces: Some(HhtForces::new(alpha)),
        }
    }

    /// The members' memory (None only while lent to the system).
    pub(crate) fn forces(&self) -> Option<&HhtForces> {
        self.forces.as_ref()
    }

    /// Puts back the members' memory of a snapshot.
    pub(crate) fn restore_forces(&mut self, f: &HhtForces) {
        match self.forces.as_mut() {
            Some(mine) => mine.clone_from(f),
            None => self.forces = Some(f.clone()),
        }
    }

    /// Prepares a step from the state (x_n, t_n).
    pub(crate) fn begin(&mut self, model: &Model, xn: &[[f64; 3]], t: f64) {
        if let Some(f) = self.forces.as_mut() {
            f.begin(model, xn, t);
        }
    }

    /// Evaluates the step's equations at the iterate (x1, v1, a1), with the energy-consistent
    /// elastic force of the cables and twines.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn evaluate<P: LoadProvider + ?Sized>(
        &mut self,
        sys: &mut System,
        model: &Model,
        provider: &mut P,
        x1: &[[f64; 3]],
        v1: &[[f64; 3]],
        a1: &[[f64; 3]],
        o: &EvalOptions,
    ) -> Result<()> {
        sys.hht = self.forces.take();
        let r = sys.evaluate(model, provider, x1, v1, a1, o);
        // Later evaluations (outputs, guards) are of states, not of steps.
        self.forces = sys.hht.take();
        r
    }

    /// A converged step: the end state's own (physical) element forces replace the step
    /// forces in `sys`, so that outputs, guards, the energy balance and the next step's q_n
    /// see x_{n+1}.
    pub(crate) fn finish(&self, sys: &mut System, model: &Model) {
        sys.use_state_element_forces(model);
    }

    /// The accepted step ends at x1, time t1: the members' memory moves on.
    pub(crate) fn accept(&mut self, model: &Model, x1: &[[f64; 3]], t1: f64) {
        if let Some(f) = self.forces.as_mut() {
            f.advance(model, x1, t1);
        }
    }

    /// The change of the scheme's own energy over a step of h from x_n to x1 [J], given
    /// a_nᵀMa_n and a_{n+1}ᵀMa_{n+1}: ½h²(β − γ/2)·Δ(aᵀMa) + ΔΣΨ. The step's equations make
    /// E + ½h²(β − γ/2)·aᵀMa + ΣΨ non-increasing where E is (docs/theory/fem.md#energy-consistent-hht-alpha).
    pub(crate) fn algorithmic_energy_change(
        &self,
        model: &Model,
        x1: &[[f64; 3]],
        h: f64,
        ama: (f64, f64),
    ) -> f64 {
        let acc = 0.5 * h * h * (self.beta - 0.5 * self.gamma) * (ama.1 - ama.0);
        acc + self
            .forces
            .as_ref()
            .map_or(0.0, |f| f.psi_change(model, x1))
    }

    /// m = 1/(βh²), k = 1 − α, c = (1 − α)·γ/(βh).
    pub(crate) fn coef(&self, h: f64) -> Coef {
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        Coef {
            m: 1.0 / (beta * h * h),
            k: 1.0 - alpha,
            c: (1.0 - alpha) * gamma / (beta * h),
        }
    }

    /// Spectral radius ρ(Ω) of the scheme on an undamped linear oscillator at Ω = ωΔt: the
    /// largest |λ| of the step's amplification matrix of (x, Δt·v, Δt²·a)
    /// (docs/theory/fem.md#hht-spectral-properties); 1 at Ω = 0, (1 − α)/(1 + α) as Ω → ∞.
    pub(crate) fn spectral_radius(&self, omega_dt: f64) -> f64 {
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        let w2 = omega_dt * omega_dt;
        // Columns: the step from the unit states (x, v, a) = e_j, with Δt = 1.
        let mut m = [[0.0; 3]; 3];
        for (j, e) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .iter()
            .enumerate()
        {
            let [x0, v0, a0] = *e;
            // a1 + (1 − α)·Ω²·x1 + α·Ω²·x0 = 0, x1 = x0 + v0 + (½ − β)·a0 + β·a1.
            let pred = x0 + v0 + (0.5 - beta) * a0;
            let a1 =
                (-(1.0 - alpha) * w2 * pred - alpha * w2 * x0) / (1.0 + (1.0 - alpha) * w2 * beta);
            let x1 = pred + beta * a1;
            let v1 = v0 + (1.0 - gamma) * a0 + gamma * a1;
            for (i, c) in [x1, v1, a1].into_iter().enumerate() {
                m[i][j] = c;
            }
        }
        super::contact_resolution::spectral_radius_3(&m)
    }

    /// Newmark's a_{n+1} = (x_{n+1} − x_n − h·v_n)/(βh²) − (1/(2β) − 1)·a_n and
    /// v_{n+1} = v_n + h·[(1 − γ)·a_n + γ·a_{n+1}] of one DOF.
    #[inline]
    pub(crate) fn newmark(&self, xn: f64, vn: f64, an: f64, x1: f64, h: f64) -> (f64, f64) {
        let (beta, gamma) = (self.beta, self.gamma);
        let a = (x1 - xn - h * vn) / (beta * h * h) - (1.0 / (2.0 * beta) - 1.0) * an;
        (a, vn + h * ((1.0 - gamma) * an + gamma * a))
    }

    /// Newmark kinematics of the iterate on the free DOFs; `start` is (x_n, v_n, a_n).
    pub(crate) fn kinematics(
        &self,
        h: f64,
        sys: &System,
        start: (Nodal<'_>, Nodal<'_>, Nodal<'_>),
        x1: &[[f64; 3]],
        v1: &mut [[f64; 3]],
        a1: &mut [[f64; 3]],
    ) {
        let (x, v, acc) = start;
        for &gd in &sys.dof_of_free {
            let (i, k) = (gd / 3, gd % 3);
            let (a, vel) = self.newmark(x[i][k], v[i][k], acc[i][k], x1[i][k], h);
            a1[i][k] = a;
            v1[i][k] = vel;
        }
    }
}

/// The weights of the energy-consistent elastic force of HHT-α
/// (docs/theory/fem.md#energy-consistent-hht-alpha): α, γ = ½ + α and c_D = α·(½ − α).
#[derive(Debug, Clone, Copy)]
pub(crate) struct HhtWeights {
    pub alpha: f64,
    pub gamma: f64,
    pub c_d: f64,
}

impl HhtWeights {
    pub(crate) fn new(alpha: f64) -> Self {
        Self {
            alpha,
            gamma: 0.5 + alpha,
            c_d: alpha * (0.5 - alpha),
        }
    }

    /// The elastic force G_{n+1} on node b of a member with end vectors d0 = d_n and d1 [m],
    /// and ∂G_{n+1}/∂d1 [N/m]:
    ///
    /// ```text
    /// γ·G_{n+1} = f_dg(d_n, d_{n+1}) + c_D·(f_{n+1} − f_n − s_n) − (1 − γ)·G_n
    /// ```
    fn step_force(&self, e: &Cable, d0: [f64; 3], d1: [f64; 3], m: &HhtMemory) -> Member {
        let (fdg, kdg) = discrete_gradient(e, d0, d1);
        let f1 = elastic_force(e, d1);
        let k1 = elastic_tangent(e, d1);
        let g = self.gamma;
        Member {
            g: std::array::from_fn(|i| {
                (fdg[i] + self.c_d * (f1[i] - m.f[i] - m.s[i]) - (1.0 - g) * m.g[i]) / g
            }),
            dg: std::array::from_fn(|i| {
                std::array::from_fn(|j| (kdg[i][j] + self.c_d * k1[i][j]) / g)
            }),
            f1,
        }
    }
}

/// A member's step force G_{n+1} [N], its derivative ∂G/∂d1 [N/m] and the elastic force at
/// the end f_{n+1} [N].
struct Member {
    g: [f64; 3],
    dg: [[f64; 3]; 3],
    f1: [f64; 3],
}

/// What a tension-only member (a cable or one twine family of a net triangle) carries from
/// one step of the energy-consistent HHT-α to the next, all on node b (d = x_b − x_a) [N]:
/// the elastic force of the last step's equation G_n, the elastic force at the state
/// f_n = f(d_n) and its last increment s_n = f_n − f_{n−1}.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct HhtMemory {
    g: [f64; 3],
    f: [f64; 3],
    s: [f64; 3],
    /// The memory's energy Ψ_n = ½·c_D·(d_n − d_{n−1})·s_n [J per member] (≥ 0: the elastic
    /// force is monotone in d).
    psi: f64,
}

impl HhtMemory {
    /// A state at rest in the scheme's sense: G_n = f_n, s_n = 0.
    fn start(e: &Cable, d: [f64; 3]) -> Self {
        let f = elastic_force(e, d);
        Self {
            g: f,
            f,
            s: [0.0; 3],
            psi: 0.0,
        }
    }

    /// Ψ_{n+1} − Ψ_n of the step from d0 to d1 [J].
    fn psi_change(&self, e: &Cable, d0: [f64; 3], d1: [f64; 3], w: &HhtWeights) -> f64 {
        let f1 = elastic_force(e, d1);
        let dd = sub(d1, d0);
        let s1 = sub(f1, self.f);
        0.5 * w.c_d * dot(dd, s1) - self.psi
    }

    /// The accepted step from d0 to d1.
    fn advance(&mut self, e: &Cable, d0: [f64; 3], d1: [f64; 3], w: &HhtWeights) {
        let m = w.step_force(e, d0, d1, self);
        self.s = std::array::from_fn(|i| m.f1[i] - self.f[i]);
        self.psi = 0.5 * w.c_d * dot(sub(d1, d0), self.s);
        self.f = m.f1;
        self.g = m.g;
    }
}

/// Replaces the elastic part of `out`, a member evaluated at the end of the step (vector d1 =
/// length·direction), by the step force G_{n+1} so that HHT-α's residual, which weights this
/// force by 1 − α and the stored q_n (the physical force f_n at the start) by α, carries
/// exactly G_{n+1} plus the α-weighted damping forces:
/// force_b = T_d·u1 + (G_{n+1} − α·f_n)/(1 − α), and the tangent accordingly
/// (docs/theory/fem.md#energy-consistent-hht-alpha).
#[inline]
pub(crate) fn use_hht_force(
    e: &Cable,
    d0: [f64; 3],
    m: &HhtMemory,
    w: &HhtWeights,
    out: &mut CableEval,
) {
    if out.bad {
        return;
    }
    let u = out.force_b_dir;
    let d1 = [u[0] * out.length, u[1] * out.length, u[2] * out.length];
    let member = w.step_force(e, d0, d1, m);
    let kel = elastic_tangent(e, d1);
    let inv = 1.0 / (1.0 - w.alpha);
    for i in 0..3 {
        out.force_b[i] = out.damping_force * u[i] + (member.g[i] - w.alpha * m.f[i]) * inv;
        for j in 0..3 {
            out.k[i][j] += member.dg[i][j] * inv - kel[i][j];
        }
    }
}

/// The elastic force f(d) = W′(l)·d/l on node b [N].
fn elastic_force(e: &Cable, d: [f64; 3]) -> [f64; 3] {
    let l = norm(d);
    if !(l > 1e-9 * e.l0) {
        return [0.0; 3];
    }
    let t = cable::elastic_tension(e, l) / l;
    [t * d[0], t * d[1], t * d[2]]
}

/// ∂f/∂d [N/m]: (s·EA/L0)·u⊗u + (W′/l)·(I − u⊗u).
fn elastic_tangent(e: &Cable, d: [f64; 3]) -> [[f64; 3]; 3] {
    let l = norm(d);
    if !(l > 1e-9 * e.l0) {
        return [[0.0; 3]; 3];
    }
    let u = [d[0] / l, d[1] / l, d[2] / l];
    let s = if l > e.l0 { 1.0 } else { e.rc };
    let (km, kg) = (s * e.ea / e.l0, cable::elastic_tension(e, l) / l);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let p = if i == j { 1.0 } else { 0.0 } - u[i] * u[j];
            km * u[i] * u[j] + kg * p
        })
    })
}

/// Gonzalez's discrete gradient of the member's strain energy between d0 and d1 (on node b,
/// [N]) and its derivative ∂/∂d1 [N/m]: f_dg = τ·d_m, d_m = ½(d0 + d1),
/// τ = 2·(W(l1) − W(l0))/(l1² − l0²), so that (d1 − d0)·f_dg = W(l1) − W(l0) exactly, and
/// ∂f_dg/∂d1 = ½τ·I + d_m⊗κ·d1. With both ends on one side of the kink, W = ½k_s·(l − L0)²
/// (k_s = EA/L0 taut, r_c·EA/L0 slack) gives the closed forms τ = k_s·(1 − 2L0/(l0 + l1)) and
/// κ = 2·k_s·L0/((l0 + l1)²·l1), free of the cancellation of W(l1) − W(l0) at small steps;
/// across the kink κ = 2·(W′(l1)/l1 − τ)/(l1² − l0²).
fn discrete_gradient(e: &Cable, d0: [f64; 3], d1: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let (q0, q1) = (dot(d0, d0), dot(d1, d1));
    let (l0, l1) = (q0.sqrt(), q1.sqrt());
    let (taut0, taut1) = (l0 > e.l0, l1 > e.l0);
    let (tau, kappa) = if taut0 == taut1 {
        let ks = if taut1 { 1.0 } else { e.rc } * e.ea / e.l0;
        let sum = l0 + l1;
        (
            ks * (1.0 - 2.0 * e.l0 / sum),
            2.0 * ks * e.l0 / (sum * sum * l1),
        )
    } else {
        let dq = q1 - q0;
        let tau = 2.0 * (cable::energy_at_length(e, l1) - cable::energy_at_length(e, l0)) / dq;
        (tau, 2.0 * (cable::elastic_tension(e, l1) / l1 - tau) / dq)
    };
    let dm = [
        0.5 * (d0[0] + d1[0]),
        0.5 * (d0[1] + d1[1]),
        0.5 * (d0[2] + d1[2]),
    ];
    let k = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let id = if i == j { 0.5 * tau } else { 0.0 };
            id + dm[i] * kappa * d1[j]
        })
    });
    ([tau * dm[0], tau * dm[1], tau * dm[2]], k)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The members' memory of the energy-consistent HHT-α and the start positions x_n of the
/// step being solved (docs/theory/fem.md#energy-consistent-hht-alpha).
#[derive(Debug, Clone)]
pub(crate) struct HhtForces {
    pub w: HhtWeights,
    /// x_n of the step [m].
    pub xn: Vec<[f64; 3]>,
    /// One memory per cable element.
    pub cable: Vec<HhtMemory>,
    /// One memory per twine family (U, V) of each net triangle.
    pub net: Vec<[HhtMemory; 2]>,
    /// The time t_n the memory belongs to [s] (NaN: none yet).
    t: f64,
}

impl HhtForces {
    fn new(alpha: f64) -> Self {
        Self {
            w: HhtWeights::new(alpha),
            xn: Vec::new(),
            cable: Vec::new(),
            net: Vec::new(),
            t: f64::NAN,
        }
    }

    /// Prepares a step from the state (x_n, t_n): the memory starts afresh (G_n = f_n,
    /// s_n = 0) unless it belongs to t_n — after a replaced state it does not (a restored
    /// snapshot brings its own).
    fn begin(&mut self, model: &Model, xn: &[[f64; 3]], t: f64) {
        self.xn.clear();
        self.xn.extend_from_slice(xn);
        let (els, tris) = (model.elements(), model.net_triangles());
        if self.t == t && self.cable.len() == els.len() && self.net.len() == tris.len() {
            return;
        }
        self.cable.clear();
        self.cable.extend(
            els.iter()
                .map(|e| HhtMemory::start(e, sub(xn[e.b], xn[e.a]))),
        );
        self.net.clear();
        self.net.extend(tris.iter().map(|t| {
            let (u, v) = t.twine_vectors(xn);
            [HhtMemory::start(&t.twine, u), HhtMemory::start(&t.twine, v)]
        }));
        self.t = t;
    }

    /// The change of the members' memory energy ΣΨ over the step from x_n to x1 [J].
    fn psi_change(&self, model: &Model, x1: &[[f64; 3]]) -> f64 {
        let (w, xn) = (&self.w, &self.xn);
        let mut d = 0.0;
        for (e, m) in model.elements().iter().zip(&self.cable) {
            d += m.psi_change(e, sub(xn[e.b], xn[e.a]), sub(x1[e.b], x1[e.a]), w);
        }
        for (t, m) in model.net_triangles().iter().zip(&self.net) {
            let (u0, v0) = t.twine_vectors(xn);
            let (u1, v1) = t.twine_vectors(x1);
            d += t.area_uv
                * (m[0].psi_change(&t.twine, u0, u1, w) + m[1].psi_change(&t.twine, v0, v1, w));
        }
        d
    }

    /// The accepted step from x_n (kept since `begin`) to x1 at time t1.
    fn advance(&mut self, model: &Model, x1: &[[f64; 3]], t1: f64) {
        let (w, xn) = (&self.w, &self.xn);
        for (e, m) in model.elements().iter().zip(&mut self.cable) {
            m.advance(e, sub(xn[e.b], xn[e.a]), sub(x1[e.b], x1[e.a]), w);
        }
        for (t, m) in model.net_triangles().iter().zip(&mut self.net) {
            let (u0, v0) = t.twine_vectors(xn);
            let (u1, v1) = t.twine_vectors(x1);
            m[0].advance(&t.twine, u0, u1, w);
            m[1].advance(&t.twine, v0, v1, w);
        }
        self.t = t1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn member(rc: f64) -> Cable {
        Cable {
            a: 0,
            b: 1,
            l0: 1.0,
            ea: 1e4,
            rc,
            ca: 0.0,
            mu: 1.0,
            group: 0,
            contact_diameter: 0.0,
        }
    }

    /// A member that stays taut along one axis has the affine force EA/L0·(d − L0): there the
    /// step force must be HHT-α's own, (1 − α)·f(d_{n+1}) + α·f(d_n), at every step from rest,
    /// so that the linearised scheme is HHT-α (docs/theory/fem.md#energy-consistent-hht-alpha).
    #[test]
    fn a_linear_member_gets_hht_alpha_s_own_force() {
        let e = member(0.0);
        for alpha in [0.0, 0.05, 0.3] {
            let w = HhtWeights::new(alpha);
            let d = |k: usize| {
                [
                    1.1 + 0.05 * (0.7 * k as f64).sin() + 1e-3 * k as f64,
                    0.0,
                    0.0,
                ]
            };
            let mut m = HhtMemory::start(&e, d(0));
            for k in 0..200 {
                let (d0, d1) = (d(k), d(k + 1));
                let g = w.step_force(&e, d0, d1, &m).g[0];
                let hht = (1.0 - alpha) * e.ea * (d1[0] - 1.0) + alpha * e.ea * (d0[0] - 1.0);
                assert!(
                    (g - hht).abs() < 1e-9 * hht.abs(),
                    "alpha {alpha} step {k}: {g} vs {hht}"
                );
                m.advance(&e, d0, d1, &w);
            }
        }
    }

    /// Across the slack kink, and turning, the discrete gradient does the work of the strain
    /// energy exactly: Δd·f_dg = W(l1) − W(l0) = ½·EA/L0·(l1 − L0)² for a member slack at d0.
    #[test]
    fn the_discrete_gradient_does_the_strain_work_across_the_kink() {
        let e = member(0.0);
        let (d0, d1) = ([0.6, 0.5, 0.0], [0.3, 1.0, 0.4]);
        let (f, _) = discrete_gradient(&e, d0, d1);
        let work = dot(sub(d1, d0), f);
        let l1 = norm(d1);
        let exact = 0.5 * e.ea / e.l0 * (l1 - e.l0).powi(2);
        assert!((work - exact).abs() < 1e-12 * exact, "{work} vs {exact}");
    }

    /// The tangent of the step force is its derivative (central differences).
    #[test]
    fn the_step_force_tangent_matches_finite_differences() {
        let w = HhtWeights::new(0.3);
        for (rc, d0, d1) in [
            (0.0, [0.6, 0.5, 0.0], [0.3, 1.0, 0.4]),
            (0.0, [1.02, 0.0, 0.1], [1.01, 0.05, 0.12]),
            (1.0, [0.9, 0.1, 0.0], [0.95, 0.12, 0.01]),
        ] {
            let e = member(rc);
            let mut m = HhtMemory::start(&e, [1.0, 0.2, 0.0]);
            m.advance(&e, [1.0, 0.2, 0.0], d0, &w);
            let dg = w.step_force(&e, d0, d1, &m).dg;
            let hstep = 1e-6;
            for j in 0..3 {
                let (mut p, mut q) = (d1, d1);
                p[j] += hstep;
                q[j] -= hstep;
                let (gp, gq) = (w.step_force(&e, d0, p, &m).g, w.step_force(&e, d0, q, &m).g);
                for i in 0..3 {
                    let fd = (gp[i] - gq[i]) / (2.0 * hstep);
                    assert!(
                        (fd - dg[i][j]).abs() < 1e-5 * e.ea,
                        "rc {rc} [{i}][{j}]: {fd} vs {}",
                        dg[i][j]
                    );
                }
            }
        }
    }
}
