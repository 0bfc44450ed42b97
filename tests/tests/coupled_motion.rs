//! `motion = "coupled"`: a `[[prescribed]]` group that only a coupling drives needs no motion
//! keys; `aqua run` refuses it with a message that says why, `aqua check` holds it in place,
//! and a coupling drives it like any other prescribed group.

mod common;
use aqua_sim::Prescribed;
use aqua_sim::coupling::{Coupling, Target};
use common::scratch;

fn chain(prescribed: &str) -> String {
    format!(
        "[sea]\ndepth = 50.0\n\n[[line]]\nname = \"chain\"\nanchor = [0.0, 0.0, -50.0]\n\
         fairlead = [60.0, 0.0, -5.0]\nlength = 80.0\nsegments = 16\ndiameter = 0.1\n\
         mass_per_length = 50.0\nea = 1.0e8\n\n[[prescribed]]\nnodes = \"chain/fairlead\"\n\
         {prescribed}\n\n[analysis]\nkind = \"static+dynamic\"\n\n[analysis.dynamic]\n\
         dt = 0.1\nt_end = 1.0\n"
    )
}

fn scene(name: &str, text: &str) -> aqua_sim::Result<aqua_sim::scene::Scene> {
    let dir = scratch(name);
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    aqua_sim::read_scene(aqua_sim::SceneInput::File(&path), &[])
}

#[test]
fn a_coupled_group_needs_no_motion_keys_and_a_coupling_drives_it() {
    let text = chain("motion = \"coupled\"");
    // The coupling: the fairlead pulled 0.5 m out over one step raises the force on it.
    let mut sim = Coupling::new(scene("coupled", &text).unwrap()).unwrap();
    let f0 = sim.init().unwrap();
    let rest = sim.points()[0].rest[0];
    let target = Target {
        position: vec![[rest[0] + 0.5, rest[1], rest[2]]],
        ..Default::default()
    };
    let f1 = sim.step(0.0, 0.1, &[(0, target)], &[]).unwrap();
    let norm = |f: &[f64; 3]| (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    assert!(norm(&f1[0][0]) > norm(&f0[0][0]), "{f0:?} -> {f1:?}");
    sim.close().unwrap();

    // `aqua check` builds it (the nodes held in place); a run refuses it and says why.
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::scene(
        scene("check", &text).unwrap(),
    ))
    .expect("a coupled scene passes the check");
    let Err(e) = aqua_sim::run::Simulation::new(&prep) else {
        panic!("a run refuses a coupled motion")
    };
    let e = e.to_string();
    assert!(e.contains("coupled") && e.contains("aqua.Coupling"), "{e}");
}

#[test]
fn a_coupled_group_with_a_motion_key_is_an_error_naming_it() {
    let text = chain("motion = \"coupled\"\noffset = [1.0, 0.0, 0.0]");
    let Err(e) = aqua_sim::prepare(
        aqua_sim::PrepareOptions::scene(scene("offset", &text).unwrap())
            .with_prescribed(Prescribed::External),
    ) else {
        panic!("offset with a coupled motion is refused")
    };
    let e = e.to_string();
    assert!(e.contains("offset") && e.contains("coupled"), "{e}");
}
