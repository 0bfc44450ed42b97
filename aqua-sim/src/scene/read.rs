//! Reading a scene file: the raw tables with their spans, the split of keys between crates,
//! the typed scene, `--set` changes, and errors that name the file, the line, the section and
//! the key.

use super::analysis::AnalysisSpec;
use super::hydro::{LINE_HYDRO_KEYS, NET_HYDRO_KEYS, NetHydro};
use super::schema::{
    CageSpec, FarmSpec, FixSpec, GroupSpec, LineSpec, Located, MeshSpec, PanelSpec, Scene,
    SceneWake,
};
use super::sea::SeaSection;
use crate::body::BodySpec;
use crate::buoy::{BuoyShape, BuoySpec, FARM_BUOY_KEYS};
use crate::error::{Result, SimError};
use crate::overrides::Override;
use aqua_env::SeaSpec;
use aqua_mesh::{FarmParams, GmshParams};
use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::{Spanned, Table, Value};

/// Reads a file to a string, with an input error naming it.
pub fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .map_err(|e| SimError::input(format!("{}: cannot read: {e}", path.display())))
}

/// Reads the `[sea]` table of a scene file (a file holding only sea keys at top level is
/// accepted too, so a bare sea description can be shared between scenes); its `[sea.seabed]`
/// is checked and left out.
pub fn read_sea(path: &Path) -> Result<SeaSpec> {
    /// A scene seen only for its `[sea]` table; the other sections are checked elsewhere.
    #[derive(serde::Deserialize)]
    struct SeaOnly {
        sea: SeaSection,
        #[serde(flatten)]
        _rest: toml::Table,
    }
    let text = read_text(path)?;
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| SimError::input(format!("{}: {e}", path.display())))?;
    let err = |e: toml::de::Error| SimError::input(format!("{}: {e}", path.display()));
    let section = if table.contains_key("sea") {
        toml::from_str::<SeaOnly>(&text)
            .map(|s| s.sea)
            .map_err(err)?
    } else {
        toml::from_str::<SeaSection>(&text).map_err(err)?
    };
    section.check_seabed(path)?;
    Ok(section.sea)
}

/// The raw file: typed where the schema is ours, tables with spans where keys are split
/// between crates.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    sea: SeaSection,
    #[serde(default)]
    cage: Vec<Spanned<Table>>,
    #[serde(default)]
    panel: Vec<Spanned<Table>>,
    #[serde(default)]
    line: Vec<Spanned<Table>>,
    #[serde(default)]
    mesh: Vec<Spanned<Table>>,
    #[serde(default)]
    farm: Vec<Spanned<Table>>,
    #[serde(default)]
    wake: SceneWake,
    #[serde(default)]
    group: Vec<Spanned<Table>>,
    #[serde(default)]
    point: Vec<Spanned<Table>>,
    #[serde(default)]
    buoy: Vec<Spanned<Table>>,
    #[serde(default)]
    body: Vec<Spanned<Table>>,
    #[serde(default)]
    fix: Vec<Spanned<Table>>,
    #[serde(default)]
    prescribed: Vec<Spanned<Table>>,
    #[serde(default)]
    analysis: AnalysisSpec,
}

/// 1-based line number of a byte offset.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Moves the listed keys of `table` into a new table.
pub(super) fn split_keys(table: &mut Table, keys: &[&str]) -> Table {
    let mut out = Table::new();
    for k in keys {
        if let Some(v) = table.remove(*k) {
            out.insert((*k).to_string(), v);
        }
    }
    out
}

pub(super) struct Ctx<'a> {
    pub(super) path: &'a Path,
    pub(super) text: &'a str,
}

impl Ctx<'_> {
    pub(super) fn err(
        &self,
        section: &str,
        index: usize,
        line: usize,
        msg: impl std::fmt::Display,
    ) -> SimError {
        SimError::input(format!(
            "{}: line {line}: [[{section}]] #{}: {msg}",
            self.path.display(),
            index + 1
        ))
    }

    pub(super) fn typed<T: DeserializeOwned>(
        &self,
        section: &str,
        index: usize,
        line: usize,
        prefix: &str,
        table: Table,
    ) -> Result<T> {
        Value::Table(table).try_into::<T>().map_err(|e| {
            let msg = e.to_string();
            let msg = msg.trim();
            if prefix.is_empty() {
                self.err(section, index, line, msg)
            } else {
                self.err(section, index, line, format!("in {prefix}: {msg}"))
            }
        })
    }

    /// Every table of a section, typed by `f(index, line, table)`, with its line.
    pub(super) fn each<T>(
        &self,
        list: &[Spanned<Table>],
        mut f: impl FnMut(usize, usize, Table) -> Result<T>,
    ) -> Result<Vec<Located<T>>> {
        list.iter()
            .enumerate()
            .map(|(i, s)| {
                let line = line_of(self.text, s.span().start);
                f(i, line, s.get_ref().clone()).map(|value| Located { line, value })
            })
            .collect()
    }

    /// A `[[mesh]]`: gmsh files are found relative to the scene file.
    fn gmsh(&self, i: usize, line: usize, mut t: Table) -> Result<MeshSpec> {
        let net_hydro = self.net_hydro("mesh", i, line, &mut t)?;
        let mut params: GmshParams = self.typed("mesh", i, line, "", t)?;
        if params.file.is_relative()
            && let Some(dir) = self.path.parent()
        {
            params.file = dir.join(&params.file);
        }
        Ok(MeshSpec { params, net_hydro })
    }

    /// A `[[farm]]`: its grid keys, its `[farm.cage]` (typed first, so that a mistake in
    /// it is reported as such), whose `net.*` keys are split as a `[[cage]]`'s, its
    /// `[farm.buoy]` (a [`BuoySpec`] of [`FARM_BUOY_KEYS`]) and its `[[farm.slot]]`s
    /// (crate::scene::slots).
    fn farm(&self, i: usize, line: usize, mut t: Table) -> Result<FarmSpec> {
        let slots = t.remove("slot");
        let buoy = t.remove("buoy");
        match t.remove("cage") {
            Some(Value::Table(mut c)) => {
                let raw = c.clone();
                let net_hydro = self.net_hydro("farm", i, line, &mut c)?;
                let cage = self.typed("farm", i, line, "cage", c)?;
                let params: FarmParams = self.typed("farm", i, line, "", t)?;
                let buoy = buoy.map(|b| self.farm_buoy(i, line, b)).transpose()?;
                params
                    .check_cage("cage", &cage)
                    .map_err(|e| self.err("farm", i, line, e))?;
                let slot = self.farm_slots(i, line, slots, &raw, &params)?;
                Ok(FarmSpec {
                    params,
                    cage: CageSpec {
                        params: cage,
                        net_hydro,
                    },
                    buoy,
                    slot,
                })
            }
            Some(other) => Err(self.err(
                "farm",
                i,
                line,
                format!(
                    "cage = {other}: cage must be a table ([farm.cage] with type = \"CSM\", …)"
                ),
            )),
            None => {
                let _: FarmParams = self.typed("farm", i, line, "", t)?;
                buoy.map(|b| self.farm_buoy(i, line, b)).transpose()?;
                Err(self.err(
                    "farm",
                    i,
                    line,
                    "cage is missing: add a [farm.cage] table (the cage of every slot: type = \
                     \"CCT\", \"CCS\", \"CSM\" or \"SSM\" and its [[cage]] keys)",
                ))
            }
        }
    }

    /// A `[farm.buoy]`: only [`FARM_BUOY_KEYS`], `volume` required, typed as a [`BuoySpec`]
    /// of shape `cylinder` (the farm's other defaults are [`BuoySpec::resolve_farm`]'s).
    fn farm_buoy(&self, i: usize, line: usize, b: Value) -> Result<BuoySpec> {
        let in_buoy = |msg: &str| self.err("farm", i, line, format!("{}\nin `buoy`", msg.trim()));
        if let Value::Table(t) = &b {
            if let Some(k) = t.keys().find(|k| !FARM_BUOY_KEYS.contains(&k.as_str())) {
                let valid: Vec<String> = FARM_BUOY_KEYS.iter().map(|k| format!("`{k}`")).collect();
                return Err(in_buoy(&format!(
                    "unknown field `{k}`, expected one of {}",
                    valid.join(", ")
                )));
            }
            if !t.contains_key("volume") {
                return Err(in_buoy("missing field `volume`"));
            }
        }
        let spec: BuoySpec = b.try_into().map_err(|e| in_buoy(&e.to_string()))?;
        Ok(BuoySpec {
            shape: BuoyShape::Cylinder,
            ..spec
        })
    }

    /// A `[[group]]`: its name, Morison keys and section overrides.
    fn group(&self, i: usize, line: usize, mut t: Table) -> Result<GroupSpec> {
        let name = match t.remove("name") {
            Some(Value::String(n)) => Some(n),
            Some(v) => {
                return Err(self.err("group", i, line, format!("name = {v}: a group name string")));
            }
            None => None,
        };
        // The other keys first: a misspelled `name` is reported as the unknown key it is.
        let hydro = self.typed("group", i, line, "", split_keys(&mut t, LINE_HYDRO_KEYS))?;
        let section = self.typed("group", i, line, "", t)?;
        let name = name.ok_or_else(|| {
            self.err(
                "group",
                i,
                line,
                "name is missing: the element group to set (e.g. \"ropes\")",
            )
        })?;
        Ok(GroupSpec {
            name,
            section,
            hydro,
        })
    }

    /// A `[[fix]]` with its DOFs checked.
    fn fix(&self, i: usize, line: usize, t: Table) -> Result<FixSpec> {
        let value: FixSpec = self.typed("fix", i, line, "", t)?;
        if let Some(d) = value
            .dofs
            .iter()
            .find(|d| !matches!(d.as_str(), "x" | "y" | "z"))
        {
            return Err(self.err(
                "fix",
                i,
                line,
                format!("dofs contains \"{d}\": valid are \"x\", \"y\", \"z\""),
            ));
        }
        Ok(value)
    }

    /// Splits the hydrodynamic `net.*` keys off an object table.
    pub(super) fn net_hydro(
        &self,
        section: &str,
        index: usize,
        line: usize,
        table: &mut Table,
    ) -> Result<NetHydro> {
        let hydro = match table.get_mut("net") {
            Some(Value::Table(net)) => split_keys(net, NET_HYDRO_KEYS),
            Some(other) => {
                return Err(self.err(
                    section,
                    index,
                    line,
                    format!("net = {other}: net must be a table of net.* keys"),
                ));
            }
            None => Table::new(),
        };
        self.typed(section, index, line, "net", hydro)
    }
}

/// Where [`read_scene`] reads a scene from.
#[derive(Debug, Clone, Copy)]
pub enum SceneInput<'a> {
    /// A scene file: its text, and its name in messages, the default scene name and the folder
    /// that relative gmsh files are found in.
    File(&'a Path),
    /// The text of a scene; `path` names it as a file would (it need not exist).
    Text {
        /// The TOML text.
        text: &'a str,
        /// The file it stands for.
        path: &'a Path,
    },
}

/// Reads and type-checks a scene, changed by `overrides` (crate::overrides) applied in order
/// (none: the scene as it is). The scene itself must be valid; each change is then checked
/// exactly like the file, and the first one that makes the scene invalid is named in the
/// error. Messages keep the file's line numbers.
pub fn read_scene(input: SceneInput<'_>, overrides: &[Override]) -> Result<Scene> {
    match input {
        SceneInput::File(path) => parse_scene(&read_text(path)?, path, overrides),
        SceneInput::Text { text, path } => parse_scene(text, path, overrides),
    }
}

/// [`read_scene`] of a text.
fn parse_scene(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene> {
    let raw: RawScene = toml::from_str(text)
        .map_err(|e| sweep_file_error(path, text).unwrap_or_else(|| file_error(path, e)))?;
    let ctx = Ctx { path, text };
    if overrides.is_empty() {
        return ctx.scene(raw, Vec::new());
    }
    // The file must stand on its own first, so that its own mistakes are reported as such.
    ctx.scene(raw, Vec::new())?;
    let mut table: Table = toml::from_str(text).map_err(|e| file_error(path, e))?;
    let mut scene = None;
    for (k, o) in overrides.iter().enumerate() {
        let named = |msg: String| SimError::input(format!("{}: --set {o}: {msg}", path.display()));
        o.apply(&mut table).map_err(|e| named(e.to_string()))?;
        let edited = toml::to_string(&table).map_err(|e| named(e.to_string()))?;
        let raw: RawScene = toml::from_str(&edited).map_err(|e| named(e.to_string()))?;
        // Keep the file's spans so that messages and diagnostics give its line numbers.
        let base: RawScene = toml::from_str(text).map_err(|e| file_error(path, e))?;
        let raw = raw.with_spans_of(base);
        let done = overrides[..=k].iter().map(|o| o.to_string()).collect();
        let prefix = format!("{}: ", path.display());
        scene = Some(ctx.scene(raw, done).map_err(|e| {
            let msg = e.to_string();
            named(msg.strip_prefix(&prefix).unwrap_or(&msg).to_string())
        })?);
    }
    Ok(scene.expect("at least one override"))
}

fn file_error(path: &Path, e: toml::de::Error) -> SimError {
    SimError::input(format!("{}: {e}", path.display()))
}

/// A sweep file (it names the `scene` it varies) given where a scene is expected: say so.
fn sweep_file_error(path: &Path, text: &str) -> Option<SimError> {
    let table: Table = toml::from_str(text).ok()?;
    table.get("scene")?.as_str()?;
    Some(SimError::input(format!(
        "{}: this is a sweep file (it names the `scene` it varies), not a scene; run its cases \
         with `aqua sweep {}`",
        path.display(),
        path.display()
    )))
}

impl RawScene {
    /// The same tables with the spans of `base` (the unchanged file; overrides never add or
    /// remove array entries).
    fn with_spans_of(mut self, base: RawScene) -> RawScene {
        fn respan(list: &mut [Spanned<Table>], base: Vec<Spanned<Table>>) {
            for (t, b) in list.iter_mut().zip(base) {
                *t = Spanned::new(b.span(), std::mem::take(t.get_mut()));
            }
        }
        respan(&mut self.cage, base.cage);
        respan(&mut self.panel, base.panel);
        respan(&mut self.line, base.line);
        respan(&mut self.mesh, base.mesh);
        respan(&mut self.farm, base.farm);
        respan(&mut self.group, base.group);
        respan(&mut self.point, base.point);
        respan(&mut self.buoy, base.buoy);
        respan(&mut self.body, base.body);
        respan(&mut self.fix, base.fix);
        respan(&mut self.prescribed, base.prescribed);
        self
    }
}

impl Ctx<'_> {
    /// The typed scene of a raw file.
    fn scene(&self, raw: RawScene, overrides: Vec<String>) -> Result<Scene> {
        let (ctx, path) = (self, self.path);
        let name = raw.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into())
        });
        if name.is_empty() || name.contains(['/', '\\']) {
            return Err(SimError::input(format!(
                "{}: name = \"{name}\": a non-empty scene name without path separators",
                path.display()
            )));
        }
        raw.sea.check_seabed(path)?;
        Ok(Scene {
            name,
            path: path.to_path_buf(),
            sea: raw.sea.sea,
            seabed: raw.sea.seabed,
            cage: ctx.each(&raw.cage, |i, line, mut t| {
                let net_hydro = ctx.net_hydro("cage", i, line, &mut t)?;
                let params = ctx.typed("cage", i, line, "", t)?;
                Ok(CageSpec { params, net_hydro })
            })?,
            panel: ctx.each(&raw.panel, |i, line, mut t| {
                let net_hydro = ctx.net_hydro("panel", i, line, &mut t)?;
                let params = ctx.typed("panel", i, line, "", t)?;
                Ok(PanelSpec { params, net_hydro })
            })?,
            line: ctx.each(&raw.line, |i, line, mut t| {
                let hydro = ctx.typed("line", i, line, "", split_keys(&mut t, LINE_HYDRO_KEYS))?;
                let params = ctx.typed("line", i, line, "", t)?;
                Ok(LineSpec { params, hydro })
            })?,
            mesh: ctx.each(&raw.mesh, |i, line, t| ctx.gmsh(i, line, t))?,
            farm: ctx.each(&raw.farm, |i, line, t| ctx.farm(i, line, t))?,
            wake: raw.wake,
            group: ctx.each(&raw.group, |i, line, t| ctx.group(i, line, t))?,
            point: ctx.each(&raw.point, |i, line, t| ctx.typed("point", i, line, "", t))?,
            buoy: ctx.each(&raw.buoy, |i, line, t| {
                let spec: BuoySpec = ctx.typed("buoy", i, line, "", t)?;
                spec.resolve().map_err(|m| ctx.err("buoy", i, line, m))?;
                Ok(spec)
            })?,
            body: ctx.each(&raw.body, |i, line, t| {
                let spec: BodySpec = ctx.typed("body", i, line, "", t)?;
                spec.resolve().map_err(|m| ctx.err("body", i, line, m))?;
                Ok(spec)
            })?,
            fix: ctx.each(&raw.fix, |i, line, t| ctx.fix(i, line, t))?,
            prescribed: ctx.each(&raw.prescribed, |i, line, t| {
                ctx.typed("prescribed", i, line, "", t)
            })?,
            analysis: raw.analysis,
            overrides,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aqua_hydro::screen::ScreenModelId;
    use std::path::PathBuf;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("aqua-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn cage_net_keys_are_split_between_mesh_and_hydro() {
        let p = write(
            "a.toml",
            "[sea]\ndepth = 60\n\n[[cage]]\ntype = \"SSM\"\nnet.solidity = 0.2\nnet.screen_model = \"S2\"\n\
             net.wake = { model = \"cheng\" }\n",
        );
        let s = read_scene(SceneInput::File(&p), &[]).unwrap();
        assert_eq!(s.name, "a");
        assert_eq!(s.cage[0].line, 4);
        assert_eq!(s.cage[0].value.params.net.solidity, Some(0.2));
        assert_eq!(s.cage[0].value.net_hydro.screen_model, ScreenModelId::S2);
    }

    #[test]
    fn errors_name_file_line_section_and_key() {
        let p = write(
            "b.toml",
            "[sea]\ndepth = 60\n\n\n[[cage]]\ntype = \"SSM\"\ncircumferense = 100\n",
        );
        let e = read_scene(SceneInput::File(&p), &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("b.toml") && e.contains("line 5") && e.contains("[[cage]] #1"),
            "{e}"
        );
        assert!(e.contains("circumferense"), "{e}");
        let p = write(
            "c.toml",
            "[[cage]]\ntype = \"SSM\"\nnet.screen_model = \"S9\"\n",
        );
        let e = read_scene(SceneInput::File(&p), &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("S9") && e.contains("S1"), "{e}");
        let p = write("d.toml", "[analysis]\nkind = \"quasi\"\n");
        let e = read_scene(SceneInput::File(&p), &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2") && e.contains("quasi") && e.contains("static+dynamic"),
            "{e}"
        );
        let p = write(
            "e.toml",
            "[[line]]\nanchor = [0,0,-50]\nlength = 10\nmorison = \"M9\"\n",
        );
        let e = read_scene(SceneInput::File(&p), &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("[[line]] #1") && e.contains("M9"), "{e}");
    }
}
