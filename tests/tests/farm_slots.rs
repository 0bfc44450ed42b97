//! `[[farm.slot]]` (docs/theory/cages.md#farm-grid): a farm cell with a cage of its own type
//! and size builds exactly as a standalone `[[cage]]` of the same keys, centred in its cell; an
//! empty cell has no cage and none of its four bridles; each cage's wake factor comes from its
//! own net; bad slots are errors naming the file, the slot's line, the value and what is valid.
//! Mesh and model building only (no solve).

mod common;
use common::*;

use aqua_mesh::Mesh;
use aqua_sim::build_mesh;
use aqua_sim::scene::{SceneInput, read_scene};
use std::path::Path;

/// The net of `[farm.cage]`: twine diameter and half mesh [m].
const TWINE: (f64, f64) = (2.85e-3, 25.87e-3);

/// A 1 × 2 farm (spacing 40 m, cells centred at x = ∓20 m, y = 0) of 20 m CSM cages, with
/// `slots` appended.
fn farm_text(slots: &str) -> String {
    format!(
        r#"[sea]
depth = 40.0

[sea.current]
kind = "uniform"
velocity = [0.3, 0.0, 0.0]

[[farm]]
name = "farm"
rows = 1
columns = 2
spacing = 40.0
grid_depth = 5.0
element_length = 5.0
anchor_length = 130.0

[farm.frame]
diameter = 0.048
ea = 2.0e7
mass_per_length = 2.3

[farm.bridle]
diameter = 0.040
ea = 1.4e7
mass_per_length = 1.6

[farm.anchor]
diameter = 0.048
ea = 2.0e7
mass_per_length = 2.3

[farm.buoy]
volume = 2.0
mass = 150.0

[farm.cage]
type = "CSM"
diameter = 20.0
depth = 8.0
cone_depth = 2.0
element_length = 4.0
sinker_weight_per_metre = 150.0
tip_weight = 300.0
net.twine_diameter = {}
net.half_mesh = {}
{slots}"#,
        TWINE.0, TWINE.1
    )
}

/// The keys every standalone comparison cage shares with `[farm.cage]` (what the slot
/// inherits), as `[[cage]]` lines.
fn inherited() -> String {
    format!(
        "depth = 8.0\ncone_depth = 2.0\nelement_length = 4.0\nsinker_weight_per_metre = 150.0\n\
         tip_weight = 300.0\nfixed = []\nnet.twine_diameter = {}\nnet.half_mesh = {}\n",
        TWINE.0, TWINE.1
    )
}

fn mesh_of(name: &str, text: &str) -> Mesh {
    let scene = scene_of(text, Path::new(&format!("{name}.toml")))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    build_mesh(&scene).unwrap().0
}

fn object(m: &Mesh, name: &str) -> Option<u32> {
    m.objects
        .iter()
        .position(|o| o.name == name)
        .map(|i| i as u32)
}

/// (nodes, lines, panels) of one object.
fn counts(m: &Mesh, name: &str) -> (usize, usize, usize) {
    let o = object(m, name).unwrap_or_else(|| panic!("no object {name}"));
    (
        m.node_owner.iter().filter(|w| w.0 == o).count(),
        m.lines.iter().filter(|l| l.object == o).count(),
        m.panels.iter().filter(|p| p.object == o).count(),
    )
}

/// Largest |x − cx| and |y − cy| and the smallest and largest distance from (cx, cy) of the
/// nodes of `group` (horizontal).
fn extent(m: &Mesh, group: &str, c: [f64; 2]) -> (f64, f64, f64, f64) {
    let nodes = m
        .resolve_nodes(group)
        .unwrap_or_else(|| panic!("no {group}"));
    let mut e = (0.0f64, 0.0f64, f64::INFINITY, 0.0f64);
    for n in nodes {
        let (dx, dy) = (m.nodes[n].x - c[0], m.nodes[n].y - c[1]);
        let r = dx.hypot(dy);
        e = (e.0.max(dx.abs()), e.1.max(dy.abs()), e.2.min(r), e.3.max(r));
    }
    e
}

#[test]
fn a_slot_cage_builds_as_a_standalone_cage_of_the_same_keys() {
    // (slot keys, the same cage's own keys) for slot (1, 2).
    let cases = [
        (
            "type = \"CCT\"\ndiameter = 16.0\nbottom_ratio = 0.75\n",
            "type = \"CCT\"\ndiameter = 16.0\nbottom_ratio = 0.75\n",
        ),
        // An SSM: the farm cage's diameter is not inherited (a size key, and not an SSM key).
        (
            "type = \"SSM\"\nside = 14.0\n",
            "type = \"SSM\"\nside = 14.0\n",
        ),
    ];
    for (k, (slot, own)) in cases.iter().enumerate() {
        let farm = mesh_of(
            "slots",
            &farm_text(&format!("\n[[farm.slot]]\nrow = 1\ncolumn = 2\n{slot}")),
        );
        let names: Vec<&str> = farm.objects.iter().map(|o| o.name.as_str()).collect();
        assert!(
            names.contains(&"farm/cage_r1c1") && names.contains(&"farm/cage_r1c2"),
            "{names:?}"
        );
        let alone = mesh_of(
            "alone",
            &format!("[[cage]]\nname = \"c\"\n{own}{}", inherited()),
        );
        let (a, b) = (counts(&farm, "farm/cage_r1c2"), counts(&alone, "c"));
        println!("case {k}: slot cage (nodes, lines, panels) = {a:?}, standalone {b:?}");
        assert_eq!(a, b, "case {k}");
        // Slot (1, 1) is still the farm's 20 m CSM: its own standalone twin.
        let csm = mesh_of(
            "csm",
            &format!(
                "[[cage]]\nname = \"c\"\ntype = \"CSM\"\ndiameter = 20.0\n{}",
                inherited()
            ),
        );
        assert_eq!(counts(&farm, "farm/cage_r1c1"), counts(&csm, "c"));
        // Sizes from the node positions, about the cell centres (x_c = (c − 1/2 − 1)·40 m).
        let (_, _, lo, hi) = extent(&farm, "farm/cage_r1c1/net_top", [-20.0, 0.0]);
        assert!(
            (lo - 10.0).abs() < 1e-9 && (hi - 10.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        let top = extent(&farm, "farm/cage_r1c2/net_top", [20.0, 0.0]);
        if k == 0 {
            // Circle of radius d/2 = 8 m at the top, bottom_ratio · 8 = 6 m at the bottom.
            assert!(
                (top.2 - 8.0).abs() < 1e-9 && (top.3 - 8.0).abs() < 1e-9,
                "{top:?}"
            );
            let bot = extent(&farm, "farm/cage_r1c2/net_bottom", [20.0, 0.0]);
            assert!(
                (bot.2 - 6.0).abs() < 1e-9 && (bot.3 - 6.0).abs() < 1e-9,
                "{bot:?}"
            );
        } else {
            // Square of half-width side/2 = 7 m, corners at 7√2 m.
            assert!(
                (top.0 - 7.0).abs() < 1e-9 && (top.1 - 7.0).abs() < 1e-9,
                "{top:?}"
            );
            assert!((top.3 - 7.0 * 2f64.sqrt()).abs() < 1e-9, "{top:?}");
        }
    }
}

/// Bridles ending on a cage's collar: each bridle has exactly one collar end.
fn bridles_on_collars(m: &Mesh) -> usize {
    let frame = object(m, "farm/frame").unwrap();
    let g = m
        .groups
        .iter()
        .find(|g| g.object == frame && g.name == "bridles")
        .unwrap();
    let collars: Vec<usize> = m
        .objects
        .iter()
        .filter(|o| o.name.starts_with("farm/cage_"))
        .flat_map(|o| m.resolve_nodes(&format!("{}/top_ring", o.name)).unwrap())
        .collect();
    g.lines
        .iter()
        .filter(|&&e| m.lines[e].nodes.iter().any(|n| collars.contains(n)))
        .count()
}

#[test]
fn an_empty_slot_has_no_cage_and_no_bridles() {
    let full = mesh_of("full", &farm_text(""));
    let empty = mesh_of(
        "empty",
        &farm_text("\n[[farm.slot]]\nrow = 1\ncolumn = 2\nempty = true\n"),
    );
    assert!(object(&full, "farm/cage_r1c2").is_some());
    assert!(object(&empty, "farm/cage_r1c2").is_none());
    assert!(object(&empty, "farm/cage_r1c1").is_some());
    assert_eq!(bridles_on_collars(&full), 8);
    assert_eq!(bridles_on_collars(&empty), 4);
    // The grid stays: 2 × 3 plates, 10 anchor lines (2(R + C + 2)).
    for m in [&full, &empty] {
        assert_eq!(m.resolve_nodes("farm/frame/plates").unwrap().len(), 6);
        let anchors = m
            .objects
            .iter()
            .filter(|o| o.name.starts_with("farm/anchor_"))
            .count();
        assert_eq!(anchors, 10);
    }
    // The counts `aqua check` prints.
    let dir = scratch("farm-slot-empty");
    let path = dir.join("empty.toml");
    std::fs::write(
        &path,
        farm_text("\n[[farm.slot]]\nrow = 1\ncolumn = 2\nempty = true\n"),
    )
    .unwrap();
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).unwrap();
    let c = &prep.built.farms[0].counts;
    assert_eq!(
        (c.cages, c.bridles, c.plates, c.anchor_lines),
        (1, 4, 6, 10)
    );
    assert_eq!(prep.built.farms[0].cages, ["farm/cage_r1c1"]);
}

#[test]
fn each_cage_wake_factor_comes_from_its_own_net() {
    let dir = scratch("farm-slot-wake");
    let path = dir.join("wake.toml");
    std::fs::write(
        &path,
        farm_text("\n[[farm.slot]]\nrow = 1\ncolumn = 2\nnet.solidity = 0.3\n"),
    )
    .unwrap();
    let prep = aqua_sim::prepare(aqua_sim::PrepareOptions::file(&path)).unwrap();
    let b = &prep.built;
    // Løland (hydrodynamics spec §6.1): r = 1 − 0.46·(Sn − 1.24Sn² + 13.7Sn³).
    let loland = |sn: f64| 1.0 - 0.46 * (sn - 1.24 * sn * sn + 13.7 * sn.powi(3));
    let q = TWINE.0 / TWINE.1;
    let farm_sn = 2.0 * q - q * q;
    assert_eq!(b.cage_wake.sources.len(), 2);
    for s in &b.cage_wake.sources {
        let name = &b.elements.wake_groups[s.group].name;
        let sn = if name.starts_with("farm/cage_r1c2") {
            0.3
        } else {
            farm_sn
        };
        println!("{name}: r = {:.6} (Sn = {sn:.4})", s.factor);
        assert!(
            (s.factor - loland(sn)).abs() < 1e-12,
            "{name}: {}",
            s.factor
        );
    }
}

/// The 1-based line of the `k`-th (1-based) `[[farm.slot]]` header in `text`.
fn slot_line(text: &str, k: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == "[[farm.slot]]")
        .nth(k - 1)
        .map(|(i, _)| i + 1)
        .unwrap()
}

#[test]
fn bad_slots_name_file_line_value_and_what_is_valid() {
    let check = |name: &str, slots: &str, slot: usize, want: &[&str]| {
        let text = farm_text(slots);
        let file = format!("{name}.toml");
        let e = match scene_of(&text, Path::new(&file)) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.to_string(),
        };
        let line = format!("line {}:", slot_line(&text, slot));
        for w in [file.as_str(), line.as_str(), "[[farm]] #1"]
            .iter()
            .chain(want)
        {
            assert!(e.contains(w), "{name}: '{w}' not in: {e}");
        }
    };
    check(
        "outside",
        "\n[[farm.slot]]\nrow = 2\ncolumn = 1\nempty = true\n",
        1,
        &["[[farm.slot]] #1", "row = 2", "1..=1", "rows = 1"],
    );
    check(
        "column-zero",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 0\nempty = true\n",
        1,
        &["column = 0", "1..=2", "columns = 2"],
    );
    check(
        "twice",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\nempty = true\n\n[[farm.slot]]\nrow = 1\n\
         column = 2\ndiameter = 12.0\n",
        2,
        &[
            "[[farm.slot]] #2",
            "row = 1, column = 2",
            "already given by [[farm.slot]] #1",
        ],
    );
    check(
        "unknown",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\ndiametre = 12.0\n",
        1,
        &[
            "[[farm.slot]] #1",
            "diametre",
            "unknown field",
            "`diameter`",
            "row, column, empty",
        ],
    );
    check(
        "unknown-net",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\nnet.solidty = 0.2\n",
        1,
        &["solidty", "`solidity`"],
    );
    check(
        "empty-with-keys",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\nempty = true\ndepth = 6.0\n",
        1,
        &["empty = true", "depth", "holds no cage"],
    );
    check(
        "no-row",
        "\n[[farm.slot]]\ncolumn = 2\nempty = true\n",
        1,
        &["missing field `row`"],
    );
    check(
        "slot-fixed",
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\nfixed = [\"top_ring\"]\n",
        1,
        &["(row 1, column 2)", "cage.fixed", "set by the farm"],
    );
    // A key the slot's type does not take is still an error when the slot gives it (found
    // when the cage is built: the message names the farm's line and the slot's object).
    let text = farm_text(
        "\n[[farm.slot]]\nrow = 1\ncolumn = 2\ntype = \"SSM\"\nside = 14.0\ntube_depth = 2.0\n",
    );
    let scene = scene_of(&text, Path::new("not-for-type.toml")).unwrap();
    let e = build_mesh(&scene).unwrap_err();
    let e = e.chain();
    for w in ["not-for-type.toml", "farm/cage_r1c2", "tube_depth", "SSM"] {
        assert!(e.contains(w), "'{w}' not in: {e}");
    }
}

/// The scene of `text`, named `path` in messages.
fn scene_of(text: &str, path: &Path) -> aqua_sim::error::Result<aqua_sim::Scene> {
    read_scene(SceneInput::Text { text, path }, &[])
}
