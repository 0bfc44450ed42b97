//! The physics of one element: the load models of net panels ([`crate::net_panel`]), Morison
//! lines ([`crate::morison_line`]) and point bodies ([`crate::point_body`]) evaluated with the
//! element's local kinematics and the cached flow, its results into a sink.

use super::*;

impl LoadAssembly {
    /// The physics of one element with local kinematics, into a sink.
    pub(super) fn compute<S: Sink>(
        &self,
        e: usize,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        want: Want,
        sink: &mut S,
        local: &mut Local,
    ) {
        let el = &self.elems[e];
        let r = self.wake[e].factor * self.cage_factor[e];
        let fl = |i: usize| &self.flow[el.nodes[i]];
        match el.kind {
            Kind::Tri | Kind::Quad => {
                let panel = &self.panels[el.idx];
                let weight = if el.kind == Kind::Quad { 0.5 } else { 1.0 };
                let mut re_lo = f64::INFINITY;
                let mut re_hi: f64 = 0.0;
                // per node: r·U_c + u_w − v, position, submergence; a piece's relative velocity
                // is the mean over its nodes (for a quad: (sum − left-out node)/3)
                let mut wn = [V3::zeros(); MAX_NODES];
                let mut pn = [V3::zeros(); MAX_NODES];
                let mut zn = [0.0; MAX_NODES];
                let mut wsum = V3::zeros();
                for i in 0..el.n {
                    let f = fl(i);
                    wn[i] = r * V3::from(f.current) + V3::from(f.wave_vel) - V3::from(v[i]);
                    wsum += wn[i];
                    pn[i] = V3::from(x[i]);
                    zn[i] = f.eta - x[i][2];
                }
                for k in 0..el.n_pieces() {
                    let nodes = el.piece(k);
                    let w = if el.kind == Kind::Quad {
                        (wsum - wn[k]) / 3.0
                    } else {
                        wsum / 3.0
                    };
                    let p = [pn[nodes[0]], pn[nodes[1]], pn[nodes[2]]];
                    let zeta = [zn[nodes[0]], zn[nodes[1]], zn[nodes[2]]];
                    // A net triangle's solidity follows its twines, and the position
                    // Jacobian with it (docs/theory/hydrodynamics.md#net-triangle-screen).
                    let (net, dsn) = match &panel.twines {
                        Some(map) => {
                            let (sn, grad) = if want.dfdx {
                                map.solidity_gradient(&p, panel.net.twine_diameter)
                            } else {
                                (map.solidity(&p, panel.net.twine_diameter), [V3::zeros(); 3])
                            };
                            let net = NetProps {
                                solidity: sn,
                                ..panel.net
                            };
                            (net, want.dfdx.then_some(grad))
                        }
                        None => (panel.net, None),
                    };
                    let mut t =
                        net_panel::triangle(&net, p, zeta, w, weight, self.rho, self.nu, want);
                    if let Some(grad) = dsn
                        && grad.iter().any(|g| g.norm_squared() > 0.0)
                    {
                        // ∂F/∂Sn by a central difference of the screen model (any model).
                        let h = 1e-6 * net.solidity;
                        let at = |sn: f64| {
                            let props = NetProps {
                                solidity: sn,
                                ..net
                            };
                            net_panel::triangle(
                                &props,
                                p,
                                zeta,
                                w,
                                weight,
                                self.rho,
                                self.nu,
                                Want::default(),
                            )
                            .force
                        };
                        let dfds = (at(net.solidity + h) - at(net.solidity - h)) / (2.0 * h);
                        for q in 0..3 {
                            t.dfdp[q] += dfds * grad[q].transpose();
                        }
                    }
                    if t.reynolds > 0.0 {
                        re_lo = re_lo.min(t.reynolds);
                        re_hi = re_hi.max(t.reynolds);
                    }
                    let f3 = t.force / 3.0;
                    for &i in nodes {
                        sink.force(i, f3);
                    }
                    if want.dfdv {
                        sink.dv(k, nodes, &(t.dfdw * (-1.0 / 9.0)));
                    }
                    if want.dfdx {
                        for q in 0..3 {
                            sink.dx(k, nodes, q, &(t.dfdp[q] / 3.0));
                        }
                    }
                }
                if re_hi > 0.0 {
                    local.panel[0] = local.panel[0].min(re_lo);
                    local.panel[1] = local.panel[1].max(re_hi);
                    if re_hi > RE_MAX {
                        local.clamped = true;
                    }
                    if matches!(
                        panel.net.model,
                        ScreenModel::S3 { cyl_cd: None } | ScreenModel::S6 { cyl_cd: None }
                    ) && re_hi / (1.0 - panel.net.solidity) > RE_CRISIS
                    {
                        local.crisis = true;
                    }
                }
            }
            Kind::Line => {
                let l = &self.lines[el.idx];
                let (f0, f1) = (fl(0), fl(1));
                let mean = |a: [f64; 3], b: [f64; 3]| 0.5 * (V3::from(a) + V3::from(b));
                let uf = r * mean(f0.current, f1.current) + mean(f0.wave_vel, f1.wave_vel);
                let af = r * mean(f0.current_acc, f1.current_acc) + mean(f0.wave_acc, f1.wave_acc);
                let w = uf - mean(v[0], v[1]);
                let xx = [V3::from(x[0]), V3::from(x[1])];
                let zeta = [f0.eta - x[0][2], f1.eta - x[1][2]];
                let out =
                    morison_line::line(&l.props, xx, zeta, w, af, self.rho, self.nu, self.g, want);
                let half = 0.5 * out.force;
                sink.force(0, half);
                sink.force(1, half);
                let m = 0.5 * out.added_mass;
                sink.mass(0, &m);
                sink.mass(1, &m);
                if want.dfdv {
                    sink.dv(0, &[0, 1], &(out.dfdw * -0.25));
                }
                if want.dfdx {
                    sink.dx(0, &[0, 1], 0, &(0.5 * out.dfdx[0]));
                    sink.dx(0, &[0, 1], 1, &(0.5 * out.dfdx[1]));
                }
                if out.reynolds > 0.0 && !matches!(l.props.model, MorisonModel::None) {
                    local.line[0] = local.line[0].min(out.reynolds);
                    local.line[1] = local.line[1].max(out.reynolds);
                }
                local.clamped |= out.clamped;
                local.capped |= out.capped;
            }
            Kind::Point => {
                let p = &self.points[el.idx];
                let f = fl(0);
                let w = V3::from(f.current) + V3::from(f.wave_vel) - V3::from(v[0]);
                let acc = V3::from(f.current_acc) + V3::from(f.wave_acc);
                let zeta = f.eta - x[0][2];
                let out = point_body::point(&p.props, zeta, w, acc, self.rho, self.g, want);
                sink.force(0, out.force);
                sink.mass(0, &out.added_mass);
                if want.dfdv {
                    sink.dv(0, &[0], &(-out.dfdw));
                }
                if want.dfdx {
                    sink.dx(0, &[0], 0, &out.dfdx);
                }
            }
        }
    }
}
