//! The text form of a [`MeshSummary`] (`aqua mesh`, `aqua check`): per object its builder
//! counts, net and twine diameters (docs/theory/cages.md#mesh-grouping) and a table of groups.

use crate::model::{NetElement, Role};
use crate::summary::MeshSummary;
use std::fmt::Write as _;

impl MeshSummary {
    /// The report as text, one line per fact; `notices` false leaves the mesh notices out (a
    /// caller that prints them as diagnostics says each once).
    pub fn to_text(&self, notices: bool) -> String {
        let mut s = String::new();
        for o in &self.objects {
            let _ = writeln!(
                s,
                "{} ({}{}; {} cop{})",
                o.name,
                o.kind,
                kind_words(&o.kind).map_or(String::new(), |w| format!(": {w}")),
                o.copies,
                if o.copies == 1 { "y" } else { "ies" }
            );
            if let Some(c) = &o.counts {
                let _ = writeln!(
                    s,
                    "  NT = {} nodes around, NN = {} side segments, BN = {} cone segments, extension \
                 segments = {}, ropes = {}; R_top = {:.4} m (top radius), R_bottom = {:.4} m",
                    c.nt, c.nn, c.bn, c.n_ext, c.ropes, c.top_radius, c.bottom_radius
                );
                let _ = writeln!(
                    s,
                    "  element lengths: ring {:.4} m, side {:.4} m, cone {:.4} m",
                    c.ring_element_length, c.side_element_length, c.cone_element_length
                );
            }
            if let Some(n) = &o.net {
                let _ = writeln!(
                    s,
                    "  net: dw0 = {} m twine diameter, l_p = {} m half mesh (knot to knot), Sn = {:.4} \
                 solidity, mean twine element {:.5} m, area {:.2} m²",
                    n.twine_diameter, n.half_mesh, n.solidity, n.mean_twine_length, n.net_area
                );
                let _ = writeln!(
                    s,
                    "  λ = {:.2}{} physical twines per numerical twine (elements {:.2} to {:.2}); twine \
                 diameters of the model: dws = {:.5} m structural (mass, buoyancy), dwe = {:.5} m \
                 elastic (stiffness), dwh = {:.4} m hydrodynamic (drag)",
                    n.lambda,
                    if n.lambda_given { " (given)" } else { "" },
                    n.lambda_range[0],
                    n.lambda_range[1],
                    n.structural_diameter,
                    n.elastic_diameter,
                    n.hydro_diameter
                );
                if n.element == NetElement::Triangle {
                    let _ = writeln!(
                        s,
                        "  net element: triangle ({} mesh, Priour): the triangles carry the twines; \
                     λ and the diameters above are not used",
                        n.orientation
                    );
                }
            }
            let _ = writeln!(
                s,
                "  {:<16} {:<14} {:>7} {:>7} {:>7} {:>11} {:>9} {:>9} {:>9}",
                "group",
                "role",
                "lines",
                "panels",
                "nodes",
                "weight [N]",
                "d [m]",
                "d_e [m]",
                "d_h [m]"
            );
            for g in &o.groups {
                let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.5}"));
                let _ = writeln!(
                    s,
                    "  {:<16} {:<14} {:>7} {:>7} {:>7} {:>11} {:>9} {:>9} {:>9}",
                    g.name,
                    role_name(g.role).as_str(),
                    g.lines,
                    g.panels,
                    g.nodes,
                    if g.weight > 0.0 {
                        format!("{:.1}", g.weight)
                    } else {
                        "-".into()
                    },
                    f(g.diameter),
                    f(g.elastic_diameter),
                    f(g.hydro_diameter)
                );
            }
            if o.groups.iter().any(|g| g.diameter.is_some()) {
                let _ = writeln!(
                    s,
                    "  d: diameter of mass and buoyancy, d_e: elastic, d_h: hydrodynamic"
                );
            }
        }
        let _ = writeln!(
            s,
            "total: {} nodes, {} lines, {} panels ({} quads, {} triangles){}",
            self.nodes,
            self.lines,
            self.panels,
            self.quads,
            self.triangles,
            if self.total_weight > 0.0 {
                format!(
                    ", builder weights (sinkers, tip, centre) {:.1} N",
                    self.total_weight
                )
            } else {
                String::new()
            }
        );
        if notices {
            for n in &self.notices {
                let _ = writeln!(s, "{n}");
            }
        }
        s
    }
}

/// The scene-file spelling of a role (its serde name).
fn role_name(role: Role) -> String {
    match serde_json::to_value(role) {
        Ok(serde_json::Value::String(name)) => name,
        _ => "?".into(),
    }
}

/// Plain words for a cage type (docs/theory/cages.md#cage-types), `None` for other objects.
fn kind_words(kind: &str) -> Option<&'static str> {
    Some(match kind {
        "CCT" => "circular cage, conical wall, sinker tube",
        "CCS" => "circular cage, conical wall, central sinker",
        "CSM" => "circular cage, straight wall, sinker masses",
        "SSM" => "square cage, straight wall, sinker masses",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use crate::PanelParams;

    /// A 4 × 3 panel of 4 × 3 divisions has (4+1)(3+1) = 20 nodes and 4·3 = 12 quads; the text
    /// names the object, its groups and the totals.
    #[test]
    fn panel_text_counts_nodes_and_quads() {
        let mut p = PanelParams::new(4.0, 3.0);
        p.divisions = Some([4, 3]);
        let text = p.build().unwrap().summary().to_text(true);
        assert!(text.starts_with("panel0 (panel; 1 copy)"), "{text}");
        let total = text.lines().find(|l| l.starts_with("total:")).unwrap();
        assert!(
            total.starts_with("total: 20 nodes,") && total.contains("(12 quads, 0 triangles)"),
            "{total}"
        );
    }
}
