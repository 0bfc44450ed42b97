//! The text form of a [`SeaSummary`] (`aqua waves`): the sea, the current, each regular wave's
//! H, T, ω, k, L, c, kh, H/L, Ursell number, the irregular sea's spectrum and band, the Hs and
//! Tp measured back from a record, and the warnings (docs/theory/waves.md).

use crate::SeaSummary;
use crate::record::MeasuredSea;
use serde::Serialize;
use std::fmt::Write as _;

/// The scene-file spelling of an enum value (its serde name).
fn key_name<T: Serialize>(v: &T) -> String {
    match toml::Value::try_from(v) {
        Ok(toml::Value::String(s)) => s,
        _ => "?".into(),
    }
}

impl SeaSummary {
    /// The summary as text, with the Hs and Tp `measured` from a record if given.
    pub fn to_text(&self, measured: Option<&MeasuredSea>) -> String {
        let s = self;
        let mut o = String::new();
        let depth = s
            .depth
            .map(|d| format!("{d} m"))
            .unwrap_or_else(|| "infinite".into());
        let _ = writeln!(
            o,
            "sea: g = {} m/s², rho = {} kg/m³, nu = {:e} m²/s, depth = {depth}",
            s.gravity, s.density, s.kinematic_viscosity
        );
        let _ = writeln!(
            o,
            "current: {}, surface velocity = [{}, {}, {}] m/s, ramp {} s",
            key_name(&s.current),
            s.current_surface_velocity[0],
            s.current_surface_velocity[1],
            s.current_surface_velocity[2],
            s.current_ramp_time
        );
        let _ = writeln!(
            o,
            "waves: {}{}, ramp {} s",
            key_name(&s.waves),
            s.stretching
                .map(|st| format!(", stretching {}", st.name()))
                .unwrap_or_default(),
            s.wave_ramp_time
        );
        if !s.regular.is_empty() {
            let _ = writeln!(
                o,
                "  {:>8} {:>8} {:>10} {:>10} {:>10} {:>8} {:>8} {:>8} {:>8} {:>8}",
                "H [m]",
                "T [s]",
                "w [rad/s]",
                "k [1/m]",
                "L [m]",
                "c [m/s]",
                "kh",
                "H/L",
                "Ursell",
                "dir"
            );
            for r in &s.regular {
                let _ = writeln!(
                    o,
                    "  {:>8.3} {:>8.3} {:>10.5} {:>10.6} {:>10.3} {:>8.3} {:>8} {:>8.4} {:>8} {:>8.1}",
                    r.height,
                    r.period,
                    r.omega,
                    r.wave_number,
                    r.wavelength,
                    r.phase_speed,
                    r.kh.map(|v| format!("{v:.3}")).unwrap_or("inf".into()),
                    r.steepness,
                    r.ursell.map(|v| format!("{v:.3}")).unwrap_or("-".into()),
                    r.direction_deg
                );
            }
        }
        if let Some(i) = &s.irregular {
            let _ = writeln!(
                o,
                "  spectrum {}: Hs = {} m, Tp = {:.3} s, gamma = {}, {} components ({}), seed {}",
                i.shape,
                i.hs.map(|v| v.to_string()).unwrap_or("-".into()),
                i.tp,
                i.gamma.map(|g| format!("{g:.3}")).unwrap_or("-".into()),
                i.components,
                key_name(&i.spacing),
                i.seed
            );
            let _ = writeln!(
                o,
                "  band [{:.4}, {:.4}] rad/s, retained m0 = {:.5} m², Hm0 = {:.4} m, dropped {:.3e} of the energy{}",
                i.omega_lo,
                i.omega_hi,
                i.m0_retained,
                i.hm0_retained,
                i.dropped_fraction,
                i.repeat_period
                    .map(|t| format!(", repeats every {t:.1} s"))
                    .unwrap_or_default()
            );
            let _ = writeln!(
                o,
                "  direction {} deg, {}",
                i.mean_direction_deg,
                i.spreading_s
                    .map(|s| format!("short-crested (cos-2s, s = {s})"))
                    .unwrap_or("long-crested".into())
            );
        }
        if let Some(m) = measured {
            let _ = writeln!(
                o,
                "  measured from a {:.0} s record at x = y = 0: Hs = {:.4} m, Tp = {:.3} s",
                m.record_seconds, m.hs, m.tp
            );
        }
        for w in &s.warnings {
            let _ = writeln!(o, "warning: {w}");
        }
        o
    }
}

#[cfg(test)]
mod tests {
    use crate::BuildOptions;
    use crate::config::WaveKind;
    use crate::sea_params::SeaParams;

    /// A deep-water Airy wave of T = 10 s: the row shows T and L = g·T²/(2π) (ω² = g·k) and
    /// the kinds by their scene spelling.
    #[test]
    fn regular_row_shows_the_deep_water_wavelength() {
        let spec = SeaParams {
            kind: Some(WaveKind::Airy),
            height: Some(1.0),
            period: Some(10.0),
            depth: Some("infinite".into()),
            ..Default::default()
        }
        .apply(Default::default())
        .unwrap();
        let (_, s) = spec.build(&BuildOptions::default()).unwrap();
        let text = s.to_text(None);
        let l = s.gravity * 100.0 / (2.0 * std::f64::consts::PI);
        let row = text.lines().find(|r| r.contains("10.000")).unwrap();
        assert!(row.contains(&format!("{l:.3}")), "{row} vs {l}");
        assert!(
            text.contains("depth = infinite") && text.contains("waves: airy"),
            "{text}"
        );
    }
}
