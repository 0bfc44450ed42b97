//! docs/guide/getting-started.md stays true: its scene and case file (the page's ```toml
//! blocks) pass `aqua check` and list their cases, and a run of the scene prints the `done:`
//! line the page shows.

use std::path::Path;
use std::process::Command;

fn aqua(dir: &Path, args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_aqua"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr),
    )
}

/// The fenced blocks of `lang` in a Markdown text.
fn blocks<'a>(text: &'a str, lang: &str) -> Vec<&'a str> {
    let open = format!("```{lang}\n");
    text.split(open.as_str())
        .skip(1)
        .map(|b| b.split("\n```").next().unwrap())
        .collect()
}

#[test]
fn the_getting_started_scene_checks_runs_and_sweeps_as_shown() {
    let page = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/guide/getting-started.md"),
    )
    .unwrap();
    let toml = blocks(&page, "toml");
    assert_eq!(toml.len(), 2, "the scene and the case file");
    let dir = std::env::temp_dir().join(format!("aqua-getting-started-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("first-cage.toml"), toml[0]).unwrap();
    std::fs::write(dir.join("first-cases.toml"), toml[1]).unwrap();

    let (ok, out) = aqua(&dir, &["check", "first-cage.toml"]);
    assert!(ok, "{out}");
    // The page shows the check's first lines as they are printed.
    let shown = blocks(&page, "console")[0];
    for line in out.lines().take(6) {
        assert!(
            shown.contains(line),
            "the page lacks {line:?} of aqua check"
        );
    }

    let (ok, out) = aqua(&dir, &["run", "first-cage.toml", "--out", "out/first-cage"]);
    assert!(ok, "{out}");
    let done = out.lines().find(|l| l.starts_with("done:")).unwrap();
    assert!(
        page.contains(done),
        "the page's run output is stale; the run prints {done:?}"
    );

    let (ok, out) = aqua(&dir, &["sweep", "first-cases.toml"]);
    assert!(ok && out.contains("3 cases of"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}
