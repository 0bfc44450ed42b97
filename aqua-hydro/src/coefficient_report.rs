//! Side-by-side comparison of the coefficient models (`aqua coeffs`): which models a model id
//! selects, and the screen tables (C_D, C_L against θ) and Morison tables (C_n, C_t against Re)
//! of every selected model on common grids
//! (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients).

use crate::coefficients::{MorisonTable, ScreenTable, morison_table, screen_table};
use crate::error::HydroError;
use crate::{MorisonModelId, ScreenModelId};
use serde::Serialize;

/// What to tabulate: the models and the flow around a twine.
#[derive(Debug, Clone, PartialEq)]
pub struct CoefficientQuery {
    /// Screen models to tabulate against θ.
    pub screens: Vec<ScreenModelId>,
    /// Morison models to tabulate against Re.
    pub morisons: Vec<MorisonModelId>,
    /// Net solidity Sn (screen models and M5).
    pub solidity: f64,
    /// Physical twine diameter dw0 [m].
    pub twine_diameter: f64,
    /// Relative flow speed U [m/s].
    pub speed: f64,
    /// Kinematic viscosity ν [m²/s].
    pub viscosity: f64,
    /// Fixed cylinder drag coefficient of S3/S6 instead of C_cyl(Re).
    pub cyl_cd: Option<f64>,
    /// C_D and C_L of the screen model "const".
    pub cd_cl: (Option<f64>, Option<f64>),
    /// Inflow angles θ [deg] of the screen tables.
    pub angles_deg: Vec<f64>,
    /// Reynolds numbers of the Morison tables.
    pub reynolds: Vec<f64>,
}

/// A model whose table could not be made (e.g. "const" without C_D).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{model}: {source}")]
pub struct ModelTableError {
    /// Model id.
    pub model: String,
    /// Why.
    pub source: HydroError,
}

/// Screen-model section of the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScreenReport {
    /// Sn.
    pub solidity: f64,
    /// dw0 [m].
    pub twine_diameter: f64,
    /// U [m/s].
    pub speed: f64,
    /// ν [m²/s].
    pub viscosity: f64,
    /// Re = U·dw0/ν.
    pub reynolds: f64,
    /// Fixed C_cyl of S3/S6, if given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cyl_cd: Option<f64>,
    /// One table per model.
    pub models: Vec<ScreenTable>,
}

/// Morison section of the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MorisonReport {
    /// Net solidity used by M5 (X = Re·Sn², capped at 100).
    pub solidity: f64,
    /// One table per model.
    pub models: Vec<MorisonTable>,
}

/// Every selected model's table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoefficientReport {
    /// Screen models, if any were asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub screen: Option<ScreenReport>,
    /// Morison models, if any were asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub morison: Option<MorisonReport>,
}

/// The models a model id selects: "all" (every screen model, "const" only when `has_cd`, and
/// M1-M5), one screen model or one Morison model; `None` for an unknown id.
pub fn select_models(
    model: &str,
    has_cd: bool,
) -> Option<(Vec<ScreenModelId>, Vec<MorisonModelId>)> {
    if model == "all" {
        let screens = ScreenModelId::ALL
            .into_iter()
            .filter(|id| *id != ScreenModelId::Const || has_cd)
            .collect();
        let morisons = vec![
            MorisonModelId::M1,
            MorisonModelId::M2,
            MorisonModelId::M3,
            MorisonModelId::M4,
            MorisonModelId::M5,
        ];
        return Some((screens, morisons));
    }
    if let Ok(id) = model.parse::<ScreenModelId>() {
        return Some((vec![id], Vec::new()));
    }
    match model.parse::<MorisonModelId>() {
        Ok(id) if !matches!(id, MorisonModelId::None | MorisonModelId::Const) => {
            Some((Vec::new(), vec![id]))
        }
        _ => None,
    }
}

/// The tables of the query's models; the twine Reynolds number of the screen models is
/// Re = U·dw0/ν.
pub fn coefficient_report(q: &CoefficientQuery) -> Result<CoefficientReport, ModelTableError> {
    Ok(CoefficientReport {
        screen: screen_report(q)?,
        morison: morison_report(q)?,
    })
}

fn table_error(id: String) -> impl Fn(HydroError) -> ModelTableError {
    move |source| ModelTableError {
        model: id.clone(),
        source,
    }
}

/// The screen section of [`coefficient_report`] (`None` without screen models).
pub fn screen_report(q: &CoefficientQuery) -> Result<Option<ScreenReport>, ModelTableError> {
    if q.screens.is_empty() {
        return Ok(None);
    }
    let re = q.speed * q.twine_diameter / q.viscosity;
    let models = q
        .screens
        .iter()
        .map(|&id| {
            screen_table(id, &q.angles_deg, q.solidity, re, q.cd_cl, q.cyl_cd)
                .map_err(table_error(id.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some(ScreenReport {
        solidity: q.solidity,
        twine_diameter: q.twine_diameter,
        speed: q.speed,
        viscosity: q.viscosity,
        reynolds: re,
        cyl_cd: q.cyl_cd,
        models,
    }))
}

/// The Morison section of [`coefficient_report`] (`None` without Morison models).
pub fn morison_report(q: &CoefficientQuery) -> Result<Option<MorisonReport>, ModelTableError> {
    if q.morisons.is_empty() {
        return Ok(None);
    }
    let models = q
        .morisons
        .iter()
        .map(|&id| morison_table(id, &q.reynolds, q.solidity).map_err(table_error(id.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some(MorisonReport {
        solidity: q.solidity,
        models,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn query(model: &str) -> CoefficientQuery {
        let (screens, morisons) = select_models(model, false).unwrap();
        CoefficientQuery {
            screens,
            morisons,
            solidity: 0.2,
            twine_diameter: 0.0024,
            speed: 0.5,
            viscosity: 1.19e-6,
            cyl_cd: None,
            cd_cl: (None, None),
            angles_deg: vec![0.0, 90.0],
            reynolds: vec![1e3],
        }
    }

    /// S1 (docs/theory/hydrodynamics.md#screen-models): C_D = 0.04 + A₁·cos θ with
    /// A₁ = −0.04 + Sn − 1.24Sn² + 13.7Sn³, C_L = B₁·sin 2θ: at θ = 0 C_D = Sn − 1.24Sn² +
    /// 13.7Sn³, at θ = 90° C_D = 0.04 and C_L = 0 at both.
    #[test]
    fn s1_at_normal_and_in_plane_flow_is_the_closed_form() {
        let r = coefficient_report(&query("S1")).unwrap();
        assert!(r.morison.is_none());
        let sc = r.screen.unwrap();
        assert!((sc.reynolds - 0.5 * 0.0024 / 1.19e-6).abs() < 1e-9);
        let rows = &sc.models[0].rows;
        let sn: f64 = 0.2;
        let cd0 = sn - 1.24 * sn * sn + 13.7 * sn.powi(3);
        assert!((rows[0].cd - cd0).abs() < 1e-12, "{}", rows[0].cd);
        assert!((rows[1].cd - 0.04).abs() < 1e-12, "{}", rows[1].cd);
        assert!(rows[0].cl.abs() < 1e-12 && rows[1].cl.abs() < 1e-12);
    }

    /// M1 (Bessonneau & Marichal 1998) is C_n = 1.2, C_t = 0.1 at every Re.
    #[test]
    fn m1_is_constant() {
        let mut q = query("M1");
        q.reynolds = vec![1.0, 1e3, 1e6];
        let r = coefficient_report(&q).unwrap();
        assert!(r.screen.is_none());
        for row in &r.morison.unwrap().models[0].rows {
            assert_eq!((row.cn, row.ct), (1.2, 0.1));
        }
    }

    #[test]
    fn selection_and_failures() {
        let (s, m) = select_models("all", false).unwrap();
        assert_eq!((s.len(), m.len()), (7, 5));
        assert_eq!(select_models("all", true).unwrap().0.len(), 8);
        assert!(select_models("S7", false).is_none());
        assert!(select_models("const", false).is_some());
        let e = coefficient_report(&query("const")).unwrap_err();
        assert_eq!(e.model, "const");
    }
}
