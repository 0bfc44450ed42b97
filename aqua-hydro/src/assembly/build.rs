//! Building an assembly from element lists: every element validated (errors name the element
//! and key), the wake groups checked, every buffer allocated once.

use super::*;

fn check_node(what: &str, e: usize, node: usize, n_nodes: usize) -> Result<(), HydroError> {
    if node < n_nodes {
        Ok(())
    } else {
        Err(HydroError::range(
            format!("{what}[{e}] node"),
            node,
            format!("node indices must be < {n_nodes} (the structure's node count)"),
        ))
    }
}

fn check_distinct(what: &str, e: usize, nodes: &[usize]) -> Result<(), HydroError> {
    for i in 0..nodes.len() {
        for j in i + 1..nodes.len() {
            if nodes[i] == nodes[j] {
                return Err(HydroError::range(
                    format!("{what}[{e}] nodes"),
                    format!("{nodes:?}"),
                    "the nodes of an element must be distinct",
                ));
            }
        }
    }
    Ok(())
}

fn check_group(what: &str, e: usize, g: Option<usize>, n: usize) -> Result<(), HydroError> {
    match g {
        Some(g) if g >= n => Err(HydroError::range(
            format!("{what}[{e}] wake_group"),
            g,
            format!("must be < {n} (number of wake groups)"),
        )),
        _ => Ok(()),
    }
}

impl LoadAssembly {
    /// Validates the elements and allocates every buffer.
    ///
    /// Errors name the element and key: solidity outside (0, 1), non-positive diameters or
    /// lengths, negative coefficients, node indices ≥ `n_nodes`, repeated nodes, unknown wake
    /// groups, M5 on a line that is not a net twine, and a wake model (other than none) on a
    /// group with no net panel or net twine to shadow.
    pub fn new(
        sea: impl Into<Arc<Sea>>,
        n_nodes: usize,
        elements: Elements,
    ) -> Result<Self, HydroError> {
        let sea = sea.into();
        let Elements {
            panels,
            lines,
            points,
            wake_groups,
        } = elements;
        let ng = wake_groups.len();
        let mut warnings = Vec::new();
        let mut warned_fit = false;
        let mut warned_high = false;
        let mut warned_s6 = false;
        let mut warned_single = false;
        for (i, g) in wake_groups.iter().enumerate() {
            if g.wake.model != WakeModel::None {
                check_solidity(
                    &format!("wake_groups[{i}] ({}) solidity", g.name),
                    g.solidity,
                )?;
            }
        }
        let mut elems = Vec::with_capacity(panels.len() + lines.len() + points.len());
        for (e, p) in panels.iter().enumerate() {
            let key = |k: &str| format!("panel[{e}] {k}");
            check_solidity(&key("solidity"), p.net.solidity)?;
            check_positive(&key("twine_diameter"), p.net.twine_diameter, "m")?;
            if let ScreenModel::Const { cd, .. } = p.net.model {
                check_non_negative(&key("cd"), cd, "-")?;
            }
            check_group("panel", e, p.wake_group, ng)?;
            let (nodes, n, kind) = match p.nodes {
                PanelNodes::Triangle(t) => ([t[0], t[1], t[2], 0], 3, Kind::Tri),
                PanelNodes::Quad(q) => (q, 4, Kind::Quad),
            };
            for &nd in &nodes[..n] {
                check_node("panel", e, nd, n_nodes)?;
            }
            check_distinct("panel", e, &nodes[..n])?;
            let sn = p.net.solidity;
            let id = p.net.model.id();
            use crate::screen::ScreenModelId as S;
            if matches!(id, S::S1 | S::S2) && !(0.13..=0.35).contains(&sn) && !warned_fit {
                warned_fit = true;
                warnings.push(format!(
                    "screen model {id}: solidity {sn} is outside 0.13-0.35, the range it was fitted for"
                ));
            }
            if sn > 0.5 && !warned_high {
                warned_high = true;
                warnings.push(format!(
                    "net solidity {sn} > 0.5 is outside the data behind every screen model"
                ));
            }
            if id == S::S6 && !warned_s6 {
                warned_s6 = true;
                warnings.push(
                    "screen model S6 is limited: drag only, no lift defined by the source".into(),
                );
            }
            if matches!(id, S::S5 | S::Bi2014)
                && p.wake_group
                    .is_some_and(|g| wake_groups[g].wake.model != WakeModel::None)
                && !warned_single
            {
                warned_single = true;
                warnings.push(format!(
                    "screen model {id} is a single-net fit; it is applied to every panel of a cage"
                ));
            }
            elems.push(Elem {
                kind,
                nodes,
                n,
                idx: e,
            });
        }
        for (e, l) in lines.iter().enumerate() {
            let key = |k: &str| format!("line[{e}] {k}");
            let pr = &l.props;
            let drag = !matches!(pr.model, MorisonModel::None);
            if drag {
                check_positive(&key("hydro_diameter"), pr.hydro_diameter, "m")?;
                check_positive(&key("reynolds_diameter"), pr.reynolds_diameter, "m")?;
            }
            check_positive(&key("volume_diameter"), pr.volume_diameter, "m")?;
            check_positive(&key("rest_length"), pr.rest_length, "m")?;
            check_non_negative(&key("added_mass"), pr.added_mass, "-")?;
            check_non_negative(&key("added_mass_axial"), pr.added_mass_axial, "-")?;
            match pr.model {
                MorisonModel::M5 { solidity } => {
                    if !l.net_twine {
                        return Err(HydroError::key(
                            key("morison"),
                            "model \"M5\" needs a net solidity and is only valid for net twines",
                        ));
                    }
                    check_solidity(&key("solidity"), solidity)?;
                }
                MorisonModel::Const { cn, ct } => {
                    check_non_negative(&key("cn"), cn, "-")?;
                    check_non_negative(&key("ct"), ct, "-")?;
                }
                _ => {}
            }
            check_group("line", e, l.wake_group, ng)?;
            for &nd in &l.nodes {
                check_node("line", e, nd, n_nodes)?;
            }
            check_distinct("line", e, &l.nodes)?;
            elems.push(Elem {
                kind: Kind::Line,
                nodes: [l.nodes[0], l.nodes[1], 0, 0],
                n: 2,
                idx: e,
            });
        }
        for (e, p) in points.iter().enumerate() {
            let key = |k: &str| format!("point[{e}] {k}");
            check_non_negative(&key("volume"), p.props.volume, "m³")?;
            match p.props.shape {
                PointShape::Prism { height } => check_non_negative(&key("height"), height, "m")?,
                PointShape::Sphere { radius } => {
                    let v = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
                    if !(radius.is_finite() && radius > 0.0) {
                        return Err(HydroError::range(key("radius"), radius, "finite and > 0 m"));
                    }
                    if (p.props.volume - v).abs() > 1e-9 * v {
                        return Err(HydroError::range(
                            key("volume"),
                            p.props.volume,
                            format!("4πR³/3 = {v} m³ for a sphere of radius {radius} m"),
                        ));
                    }
                }
            }
            check_non_negative(&key("drag_area"), p.props.drag_area, "m²")?;
            check_non_negative(&key("added_mass_coefficient"), p.props.added_mass, "-")?;
            check_node("point", e, p.node, n_nodes)?;
            elems.push(Elem {
                kind: Kind::Point,
                nodes: [p.node, 0, 0, 0],
                n: 1,
                idx: e,
            });
        }
        // wake groups: net nodes and members
        let mut group_state = vec![
            GroupState {
                net_nodes: Vec::new(),
                members: Vec::new(),
                computed: false,
            };
            ng
        ];
        for (e, el) in elems.iter().enumerate() {
            let (g, is_net, member) = match el.kind {
                Kind::Tri | Kind::Quad => {
                    let g = panels[el.idx].wake_group;
                    (g, true, true)
                }
                Kind::Line => {
                    let l = &lines[el.idx];
                    let apply = l
                        .wake_group
                        .is_some_and(|g| wake_groups[g].wake.apply_to_lines);
                    (l.wake_group, l.net_twine, l.net_twine || apply)
                }
                Kind::Point => (None, false, false),
            };
            if let Some(g) = g {
                let st = &mut group_state[g];
                if is_net {
                    st.net_nodes.extend_from_slice(&el.nodes[..el.n]);
                }
                if member && wake_groups[g].wake.model != WakeModel::None {
                    st.members.push(e);
                }
            }
        }
        for (i, st) in group_state.iter_mut().enumerate() {
            st.net_nodes.sort_unstable();
            st.net_nodes.dedup();
            let model = wake_groups[i].wake.model;
            if model != WakeModel::None && st.net_nodes.is_empty() {
                return Err(HydroError::WakeWithoutNet {
                    group: i,
                    name: wake_groups[i].name.clone(),
                    model: model.id().as_str(),
                });
            }
        }
        let mut voff = Vec::with_capacity(elems.len() + 1);
        let mut xoff = Vec::with_capacity(elems.len() + 1);
        let (mut a, mut b) = (0, 0);
        for el in &elems {
            voff.push(a);
            xoff.push(b);
            a += el.n_pieces();
            b += el.n_pieces() * el.piece_len();
        }
        voff.push(a);
        xoff.push(b);
        let mut used: Vec<usize> = elems.iter().flat_map(|e| e.nodes[..e.n].to_vec()).collect();
        used.sort_unstable();
        used.dedup();
        let all_used = used.len() == n_nodes;
        let n_scratch = if all_used { 0 } else { used.len() };
        let ne = elems.len();
        Ok(Self {
            rho: sea.density(),
            nu: sea.kinematic_viscosity(),
            g: sea.gravity(),
            sea,
            n_nodes,
            panels,
            lines,
            points,
            groups: wake_groups,
            group_state,
            elems,
            voff,
            xoff,
            used,
            all_used,
            scratch_flow: vec![FlowPoint::default(); if all_used { n_nodes } else { n_scratch }],
            flow: vec![NodeFlow::default(); n_nodes],
            flow_key: None,
            sea_counts: (0, 0),
            flow_pts: vec![[0.0; 3]; if all_used { n_nodes } else { n_scratch }],
            wake: vec![WakeCell::default(); ne],
            wake_ready: false,
            cage_wake: CageWake::default(),
            cage_receivers: Vec::new(),
            cage_factor: vec![1.0; ne],
            wake_next: vec![WakeCell::default(); ne],
            cage_next: vec![1.0; ne],
            shadows: Vec::new(),
            shadow_order: Vec::new(),
            shadow_pts: Vec::new(),
            elem_force: vec![[[0.0; 3]; MAX_NODES]; ne],
            elem_mass: vec![[[0.0; 3]; 3]; ne],
            stats: Stats::new(),
            warnings,
        })
    }
}
