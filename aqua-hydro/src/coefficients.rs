//! Coefficient tables of the load models: screen-model C_D, C_L against the inflow angle and
//! Morison C_n, C_t against the Reynolds number
//! (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients), for comparing
//! and choosing models (`aqua coeffs`).

use crate::error::HydroError;
use crate::{MorisonModel, MorisonModelId, ScreenModel, ScreenModelId};
use serde::Serialize;

/// One screen-model row.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ScreenRow {
    /// θ [deg].
    pub theta_deg: f64,
    /// C_D.
    pub cd: f64,
    /// C_L.
    pub cl: f64,
}

/// One screen model's table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScreenTable {
    /// Model id.
    pub model: String,
    /// Source.
    pub reference: String,
    /// Rows by angle.
    pub rows: Vec<ScreenRow>,
}

/// One Morison row.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MorisonRow {
    /// Reynolds number.
    pub re: f64,
    /// C_n.
    pub cn: f64,
    /// C_t.
    pub ct: f64,
}

/// One Morison model's table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MorisonTable {
    /// Model id.
    pub model: String,
    /// Source.
    pub reference: String,
    /// Rows by Reynolds number.
    pub rows: Vec<MorisonRow>,
}

/// The table of a screen model at the angles θ [deg], solidity Sn and twine Reynolds number
/// `re`; `cd_cl` is used by the "const" model, `cyl_cd` by S3 and S6.
pub fn screen_table(
    id: ScreenModelId,
    angles_deg: &[f64],
    solidity: f64,
    re: f64,
    cd_cl: (Option<f64>, Option<f64>),
    cyl_cd: Option<f64>,
) -> Result<ScreenTable, HydroError> {
    let uses_cyl = matches!(id, ScreenModelId::S3 | ScreenModelId::S6);
    let is_const = id == ScreenModelId::Const;
    let model = ScreenModel::new(
        id,
        if is_const { cd_cl.0 } else { None },
        if is_const { cd_cl.1 } else { None },
        if uses_cyl { cyl_cd } else { None },
    )?;
    let rows = angles_deg
        .iter()
        .map(|&deg| {
            let (cd, cl) = model.cd_cl(deg.to_radians(), solidity, re);
            // + 0.0 turns −0 (e.g. S4 lift at 90°) into 0 for the tables
            ScreenRow {
                theta_deg: deg,
                cd: cd + 0.0,
                cl: cl + 0.0,
            }
        })
        .collect();
    Ok(ScreenTable {
        model: id.to_string(),
        reference: id.reference().to_string(),
        rows,
    })
}

/// The table of a Morison model at the Reynolds numbers `res` (M5 uses the solidity).
pub fn morison_table(
    id: MorisonModelId,
    res: &[f64],
    solidity: f64,
) -> Result<MorisonTable, HydroError> {
    let model = MorisonModel::new(
        id,
        None,
        None,
        (id == MorisonModelId::M5).then_some(solidity),
    )?;
    let rows = res
        .iter()
        .map(|&re| {
            let k = model.coefficients(re);
            MorisonRow {
                re,
                cn: k.cn,
                ct: k.ct,
            }
        })
        .collect();
    Ok(MorisonTable {
        model: id.to_string(),
        reference: id.reference().to_string(),
        rows,
    })
}
