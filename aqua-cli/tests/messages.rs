//! What `aqua check`, `aqua mesh` and `aqua run` say about a small hand-written gmsh scene: every
//! notice once and without a doubled prefix, no notice about a default the scene has replaced,
//! no word about triangle diagonals for a quad-only net, `[[point]]` forces reported as such,
//! and no volume ratio for an open net.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-msg-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Exit code and stdout + stderr.
fn aqua(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// Two quads of net, a two-element `line:bridle` group and two fixed nodes (MSH 2.2).
const QUADS: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n2 1 \"net\"\n\
1 2 \"line:bridle\"\n0 3 \"fixed\"\n$EndPhysicalNames\n$Nodes\n6\n1 0 0 -1\n2 1 0 -1\n\
3 1 0 -2\n4 0 0 -2\n5 2 0 -1\n6 2 0 -2\n$EndNodes\n$Elements\n6\n1 3 2 1 1 1 2 3 4\n\
2 3 2 1 1 2 5 6 3\n3 1 2 2 2 1 2\n4 1 2 2 2 2 5\n5 15 2 3 3 1\n6 15 2 3 3 5\n$EndElements\n";

const SCENE: &str = "[sea]\ndepth = 30\n[sea.current]\nkind = \"uniform\"\n\
velocity = [0.3, 0, 0]\n[[mesh]]\nfile = \"net.msh\"\nMESH_EXTRA\n[[point]]\n\
nodes = \"mesh0/net_twines\"\nforce = [0, 0, -10]\n[analysis]\nkind = \"static\"\nTAIL\n";

fn scene(dir: &Path, mesh: &str, mesh_extra: &str, tail: &str) -> PathBuf {
    std::fs::write(dir.join("net.msh"), mesh).unwrap();
    let p = dir.join("net.toml");
    std::fs::write(
        &p,
        SCENE
            .replace("MESH_EXTRA", mesh_extra)
            .replace("TAIL", tail),
    )
    .unwrap();
    p
}

#[test]
fn check_says_each_notice_once_and_nothing_untrue() {
    let dir = scratch("check");
    let p = scene(&dir, QUADS, "", "");
    let (code, all) = aqua(&["check", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{all}");
    for notice in [
        "line group `bridle` uses the rope default section",
        "7 net twines derived from the unique edges of the net faces",
    ] {
        assert_eq!(all.matches(notice).count(), 1, "`{notice}` not once: {all}");
    }
    assert!(!all.contains("warning: notice"), "{all}");
    assert!(
        !all.contains("diagonal"),
        "a quad-only net has no diagonals: {all}"
    );
    assert!(!all.contains("point weights 0.0 N"), "{all}");
    assert!(
        all.contains("[[point]] #1 on mesh0/net_twines (6 nodes)")
            && all.contains("force [0.0, 0.0, -60.0] N"),
        "{all}"
    );
    // `aqua mesh --scene` prints the notices once too.
    let (code, all) = aqua(&["mesh", "--scene", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{all}");
    assert_eq!(
        all.matches("uses the rope default section").count(),
        1,
        "{all}"
    );
}

#[test]
fn no_default_section_notice_once_the_scene_sets_the_section() {
    let dir = scratch("section");
    for (extra, tail) in [
        ("groups.bridle = { diameter = 0.02 }", ""),
        ("", "[[group]]\nname = \"bridle\"\ndiameter = 0.03"),
        ("", "[[group]]\nname = \"mesh0/bridle\"\nea = 1e6"),
    ] {
        let p = scene(&dir, QUADS, extra, tail);
        let (code, all) = aqua(&["check", p.to_str().unwrap()]);
        assert_eq!(code, 0, "{all}");
        assert!(
            !all.contains("uses the rope default section"),
            "{extra}{tail}: {all}"
        );
    }
}

#[test]
fn triangles_are_mentioned_only_when_there_are_triangles() {
    let dir = scratch("tri");
    let tris = QUADS
        .replace("$Elements\n6\n", "$Elements\n7\n")
        .replace("1 3 2 1 1 1 2 3 4\n", "1 2 2 1 1 1 2 3\n7 2 2 1 1 1 3 4\n");
    let p = scene(&dir, &tris, "", "");
    let (code, all) = aqua(&["check", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{all}");
    assert!(all.contains("edges of triangles included"), "{all}");
}

#[test]
fn an_open_net_has_no_volume_ratio() {
    let dir = scratch("open");
    let p = scene(&dir, QUADS, "", "");
    let out = dir.join("out");
    let (code, all) = aqua(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{all}");
    assert!(all.contains("volume ratio n/a (no closed net)"), "{all}");
    assert!(!all.contains("volume ratio 0.0000"), "{all}");
}
