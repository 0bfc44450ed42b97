//! What a net of Priour triangles reports per triangle (docs/theory/fem.md#net-triangle): the
//! tension of one U twine and of one V twine, the solidity the screen load used and the opening
//! angle between the twines.

use crate::build::Built;
use aqua_mesh::BlockArray;
use nalgebra::Vector3;

/// The ParaView `panels` arrays of the net triangles at positions `x` (0 on other panels):
/// `twine_tension_u`, `twine_tension_v` [N], `net_solidity` and `opening_angle` [deg]. Empty
/// when the scene has no net triangles.
pub fn panel_arrays(built: &Built, x: &[[f64; 3]]) -> Vec<BlockArray> {
    if built.panel_triangle.iter().all(Option::is_none) {
        return Vec::new();
    }
    let n = built.mesh.panels.len();
    let (mut tu, mut tv, mut sn, mut angle) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (p, tri) in built.panel_triangle.iter().enumerate() {
        let Some(i) = *tri else { continue };
        let t = built.model.net_triangle_twines(i, x);
        tu[p] = t.tension_u;
        tv[p] = t.tension_v;
        angle[p] = t.opening_angle.to_degrees();
        let d = built.mesh.objects[built.mesh.panels[p].object as usize]
            .net
            .as_ref()
            .map_or(0.0, |net| net.twine_diameter);
        sn[p] = aqua_hydro::net_triangle::solidity(&Vector3::from(t.u), &Vector3::from(t.v), d);
    }
    vec![
        BlockArray::scalar("twine_tension_u", tu),
        BlockArray::scalar("twine_tension_v", tv),
        BlockArray::scalar("net_solidity", sn),
        BlockArray::scalar("opening_angle", angle),
    ]
}
