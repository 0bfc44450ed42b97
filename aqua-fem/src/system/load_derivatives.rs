//! One water-load element's force, added mass and Jacobian block, with the derivatives the
//! provider does not give formed by central finite differences
//! (docs/theory/fem.md#loads).

use super::{Coef, norm, sub};
use crate::error::{FemError, LoadError, Result};
use crate::loads::{ElementLoad, LoadProvider, MAX_LOAD_DOFS, MAX_LOAD_NODES, Want};

/// Evaluates one load element into its buffer chunk: [force 3n][added mass 9n][J (3n)²] with
/// J = −scale·(c_k·∂f/∂x + c_c·∂f/∂v).
#[allow(clippy::too_many_arguments)]
pub(super) fn load_element<P: LoadProvider + ?Sized>(
    prov: &P,
    e: usize,
    nn: usize,
    t: f64,
    xl: &[[f64; 3]; MAX_LOAD_NODES],
    vl: &[[f64; 3]; MAX_LOAD_NODES],
    want: Want,
    coef: Coef,
    scale: f64,
    fd_dfdx: bool,
    chunk: &mut [f64],
    out: &mut ElementLoad,
    tmp: &mut ElementLoad,
) -> Result<()> {
    let err = |m: LoadError| FemError::Load {
        element: e,
        error: m,
    };
    out.reset(nn);
    prov.element_load(e, t, &xl[..nn], &vl[..nn], want, out)
        .map_err(err)?;
    let nd = 3 * nn;
    for j in 0..nn {
        for k in 0..3 {
            let f = out.force[j][k];
            if !f.is_finite() {
                return Err(FemError::Load {
                    element: e,
                    error: LoadError::msg(format!("non-finite force {f} on local node {j}")),
                });
            }
            chunk[3 * j + k] = f;
            for l in 0..3 {
                chunk[3 * nn + 9 * j + 3 * k + l] = out.added_mass[j][k][l];
            }
        }
    }
    if !(want.dfdv || want.dfdx) {
        return Ok(());
    }
    let jac = &mut chunk[12 * nn..12 * nn + nd * nd];
    jac.iter_mut().for_each(|v| *v = 0.0);
    // Element size and speed for the perturbations.
    let mut size: f64 = 0.0;
    let mut speed: f64 = 0.0;
    for i in 0..nn {
        speed = speed.max(norm(vl[i]));
        for j in 0..i {
            size = size.max(norm(sub(xl[i], xl[j])));
        }
    }
    let mut fd = |wrt_x: bool, w: f64, jac: &mut [f64]| -> Result<()> {
        let h = if wrt_x {
            1e-7 * size.max(1.0)
        } else {
            1e-7 * speed.max(1.0)
        };
        for c in 0..nd {
            let mut fp = [0.0; MAX_LOAD_DOFS];
            for sgn in [1.0, -1.0] {
                let mut xp = *xl;
                let mut vp = *vl;
                if wrt_x {
                    xp[c / 3][c % 3] += sgn * h;
                } else {
                    vp[c / 3][c % 3] += sgn * h;
                }
                tmp.reset(nn);
                prov.element_load(e, t, &xp[..nn], &vp[..nn], Want::default(), tmp)
                    .map_err(err)?;
                for r in 0..nd {
                    fp[r] += sgn * tmp.force[r / 3][r % 3];
                }
            }
            for r in 0..nd {
                jac[r * nd + c] -= w * fp[r] / (2.0 * h);
            }
        }
        Ok(())
    };
    if want.dfdx && coef.k != 0.0 {
        if out.has_dfdx {
            for r in 0..nd {
                for c in 0..nd {
                    jac[r * nd + c] -= scale * coef.k * out.dfdx[r][c];
                }
            }
        } else if fd_dfdx {
            fd(true, scale * coef.k, jac)?;
        }
    }
    if want.dfdv && coef.c != 0.0 {
        if out.has_dfdv {
            for r in 0..nd {
                for c in 0..nd {
                    jac[r * nd + c] -= scale * coef.c * out.dfdv[r][c];
                }
            }
        } else {
            fd(false, scale * coef.c, jac)?;
        }
    }
    if jac.iter().any(|v| !v.is_finite()) {
        return Err(FemError::Load {
            element: e,
            error: LoadError::msg("non-finite load derivative"),
        });
    }
    Ok(())
}
