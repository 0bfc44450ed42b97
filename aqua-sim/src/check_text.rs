//! What `aqua check` prints: the [`Report`] as text — the mesh summary, the `[[point]]`
//! totals, the farms, the physics list, the cost estimate and the warnings.

use crate::check::Report;
use std::fmt::Write;
use std::path::Path;

impl Report {
    /// The text report of the scene file `file` (the mesh notices are left to the warnings,
    /// so each is said once).
    pub fn to_text(&self, file: &Path) -> String {
        let mut s = format!("scene {} ({}): valid\n", self.scene, file.display());
        s += &self.mesh.to_text(false);
        // `[[point]]` bodies are not builder weights: their totals on their own line.
        for (i, p) in self.points.iter().enumerate() {
            let _ = writeln!(
                s,
                "[[point]] #{} on {} ({} node{}): mass {:.1} kg (weight {:.1} N), force [{:.1}, \
                 {:.1}, {:.1}] N, volume {:.4} m³",
                i + 1,
                p.nodes,
                p.count,
                if p.count == 1 { "" } else { "s" },
                p.mass,
                p.weight,
                p.force[0],
                p.force[1],
                p.force[2],
                p.volume
            );
        }
        for f in &self.farms {
            let c = &f.counts;
            let _ = writeln!(
                s,
                "[[farm]] {}: {}, {} with {}, {}, {}, {}; cage-to-cage wake {}",
                f.name,
                counted(c.cages, "cage"),
                counted(c.plates, "plate"),
                counted(c.buoys, "buoy"),
                counted(c.frame_elements, "frame-line element"),
                counted(c.bridles, "bridle"),
                counted(c.anchor_lines, "anchor line"),
                if f.cage_wake { "on" } else { "off" }
            );
        }
        s += "physics:\n";
        for p in &self.physics {
            let mark = if p.active { "x" } else { " " };
            let _ = writeln!(s, "  [{mark}] {:<38} {}", p.name, p.why);
        }
        let c = &self.cost;
        let _ = writeln!(
            s,
            "cost: {} free DOFs, {} cable elements, {} load elements, {} wave components; {} \
             dynamic steps, {} output steps ({} in the ParaView series); estimated {:.1} s \
             (statics {:.1} s, dynamics {:.1} s)",
            c.dofs,
            c.cable_elements,
            c.load_elements,
            c.wave_components,
            c.steps,
            c.output_steps,
            c.paraview_steps,
            c.estimated_seconds,
            c.estimated_static_seconds,
            c.estimated_dynamic_seconds
        );
        for w in &self.warnings {
            let _ = writeln!(s, "{w}");
        }
        s
    }
}

/// "1 cage", "2 cages".
fn counted(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
