//! The coefficient tables of `aqua coeffs` as text: one column pair per model, one row per
//! angle θ (screen models) or Reynolds number (Morison models)
//! (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients).

use crate::coefficient_report::CoefficientReport;

impl CoefficientReport {
    /// The text tables: a header naming the flow and each model's reference, then the rows.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        if let Some(sc) = &self.screen {
            let _ = writeln!(
                s,
                "Screen models: Sn = {}, dw0 = {} m, U = {} m/s, nu = {:e} m2/s, Re = U*dw0/nu = {:.1}{}",
                sc.solidity,
                sc.twine_diameter,
                sc.speed,
                sc.viscosity,
                sc.reynolds,
                match sc.cyl_cd {
                    Some(c) => format!(", C_cyl = {c} (S3/S6)"),
                    None => String::new(),
                }
            );
            let _ = writeln!(
                s,
                "theta = 0 deg: flow normal to the net; 90 deg: flow in the net plane"
            );
            for m in &sc.models {
                let _ = writeln!(s, "  {:<7} {}", m.model, m.reference);
            }
            let _ = write!(s, "{:>9}", "theta_deg");
            for m in &sc.models {
                let _ = write!(
                    s,
                    " {:>10} {:>10}",
                    format!("{} Cd", m.model),
                    format!("{} Cl", m.model)
                );
            }
            let _ = writeln!(s);
            let n = sc.models.first().map_or(0, |m| m.rows.len());
            for i in 0..n {
                let _ = write!(s, "{:>9.2}", sc.models[0].rows[i].theta_deg);
                for m in &sc.models {
                    let r = m.rows[i];
                    let _ = write!(s, " {:>10.6} {:>10.6}", r.cd, r.cl);
                }
                let _ = writeln!(s);
            }
        }
        if let Some(mo) = &self.morison {
            if self.screen.is_some() {
                let _ = writeln!(s);
            }
            let _ = writeln!(
                s,
                "Morison models: Cn, Ct vs Re (Re clamped at 1e7; M5 with Sn = {})",
                mo.solidity
            );
            for m in &mo.models {
                let _ = writeln!(s, "  {:<7} {}", m.model, m.reference);
            }
            let _ = write!(s, "{:>10}", "Re");
            for m in &mo.models {
                let _ = write!(
                    s,
                    " {:>10} {:>10}",
                    format!("{} Cn", m.model),
                    format!("{} Ct", m.model)
                );
            }
            let _ = writeln!(s);
            let n = mo.models.first().map_or(0, |m| m.rows.len());
            for i in 0..n {
                let _ = write!(s, "{:>10.4e}", mo.models[0].rows[i].re);
                for m in &mo.models {
                    let r = m.rows[i];
                    let _ = write!(s, " {:>10.6} {:>10.6}", r.cn, r.ct);
                }
                let _ = writeln!(s);
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use crate::coefficient_report::{CoefficientQuery, coefficient_report, select_models};

    #[test]
    fn one_row_per_grid_value_and_one_column_pair_per_model() {
        let (screens, morisons) = select_models("S1", false).unwrap();
        let q = CoefficientQuery {
            screens,
            morisons,
            solidity: 0.2,
            twine_diameter: 0.0024,
            speed: 0.5,
            viscosity: 1e-6,
            cyl_cd: None,
            cd_cl: (None, None),
            angles_deg: vec![0.0, 45.0, 90.0],
            reynolds: Vec::new(),
        };
        let text = coefficient_report(&q).unwrap().to_text();
        let lines: Vec<&str> = text.lines().collect();
        // Flow line, θ convention, one reference line, the column header, three rows.
        assert_eq!(lines.len(), 7, "{text}");
        assert!(lines[0].contains("Re = U*dw0/nu = 1200.0"), "{}", lines[0]);
        assert_eq!(
            lines[3].split_whitespace().collect::<Vec<_>>(),
            ["theta_deg", "S1", "Cd", "S1", "Cl"]
        );
        let thetas: Vec<&str> = lines[4..]
            .iter()
            .map(|l| l.split_whitespace().next().unwrap())
            .collect();
        assert_eq!(thetas, ["0.00", "45.00", "90.00"]);
    }
}
