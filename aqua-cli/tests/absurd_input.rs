//! Physically absurd scenes are refused by `aqua check` (exit 2) with the key, the value and
//! what is valid, before any solve: a current beyond any sea's, and a structure reaching below
//! the seabed (a cage deeper than the sea, an anchor under the bed).

use std::path::PathBuf;
use std::process::Command;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

/// `aqua check EXAMPLE --set ...`: exit code and stdout + stderr.
fn check(name: &str, set: &[&str]) -> (i32, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_aqua"));
    cmd.arg("check").arg(example(name));
    for s in set {
        cmd.args(["--set", s]);
    }
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

#[test]
fn a_current_beyond_any_sea_is_refused() {
    for v in ["[1e20, 0, 0]", "[inf, 0, 0]", "[nan, 0, 0]", "[0, 8, -8]"] {
        let (code, all) = check(
            "reference-cage.toml",
            &[&format!("sea.current.velocity={v}")],
        );
        assert_eq!(code, 2, "{v}: {all}");
        assert!(all.contains("sea.current.velocity"), "{v}: {all}");
        assert!(all.contains("10 m/s"), "{v}: {all}");
    }
    // The fastest real tidal stream passes.
    let (code, all) = check("reference-cage.toml", &["sea.current.velocity=[5, 0, 0]"]);
    assert_eq!(code, 0, "{all}");
}

#[test]
fn a_structure_below_the_seabed_is_refused() {
    // The reference cage reaches z = -18 m (15 m side, 3 m cone) and the chain example's
    // anchor sits at z = -50 m: in 12 m and 40 m of water both are under the bed (the line
    // builder names its anchor, the build check the cage).
    for (name, depth, object) in [
        ("reference-cage.toml", "12", "cage"),
        ("mooring-chain.toml", "40", "chain"),
    ] {
        let (code, all) = check(name, &[&format!("sea.depth={depth}")]);
        assert_eq!(code, 2, "{name}: {all}");
        assert!(all.contains("below the seabed"), "{name}: {all}");
        assert!(all.contains(object), "{name}: {all}");
        assert!(all.contains(&format!("depth = {depth}")), "{name}: {all}");
    }
    // At their own depths, and the chain's anchor exactly on the bed, they pass.
    for name in ["reference-cage.toml", "mooring-chain.toml"] {
        let (code, all) = check(name, &[]);
        assert_eq!(code, 0, "{name}: {all}");
    }
}
