//! The `[sea]` table split between its two owners: `[sea.seabed]` is the structure's contact
//! with the bed, aqua-fem's [`SeabedSettings`]; every other key is the sea itself, aqua-env's
//! [`SeaSpec`] (docs/guide/scene.md#sea). The sea knows nothing of the structure, so the split
//! is made here, while the file is read: each part is typed by its owner, with the file's
//! spans kept for messages.

use crate::error::{Result, SimError};
use aqua_env::SeaSpec;
use aqua_fem::SeabedSettings;
use serde::Deserialize;
use serde::de::value::{MapAccessDeserializer, StringDeserializer};
use serde::de::{self, DeserializeSeed, Deserializer, IntoDeserializer, MapAccess, Visitor};
use std::path::Path;

/// The keys of `[sea]`, in the order [`SeaSpec`] declares them, then `seabed`: the "expected
/// one of" list of an unknown key (checked against [`SeaSpec`] by a test).
pub(super) const SEA_KEYS: &[&str] = &["gravity", "depth", "water", "current", "waves", "seabed"];

/// `[sea]`: the sea and the seabed's contact constants.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct SeaSection {
    /// Every `[sea]` key but `seabed` (aqua-env).
    pub sea: SeaSpec,
    /// `[sea.seabed]` (aqua-fem).
    pub seabed: SeabedSettings,
}

impl SeaSection {
    /// Checks the seabed's keys: an input error naming `sea.seabed.KEY`, the value and the valid
    /// range, after `file` (the sea's own keys are checked when the sea is built).
    pub fn check_seabed(&self, file: &Path) -> Result<()> {
        self.seabed.validate().map_err(|e| {
            SimError::input(format!(
                "{}: sea.seabed.{} = {}: {}",
                file.display(),
                e.key,
                e.value,
                e.valid
            ))
        })
    }
}

impl<'de> Deserialize<'de> for SeaSection {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        d.deserialize_map(SectionVisitor)
    }
}

struct SectionVisitor;

impl<'de> Visitor<'de> for SectionVisitor {
    type Value = SeaSection;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("the [sea] table")
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> std::result::Result<SeaSection, A::Error> {
        let mut seabed = None;
        let sea = SeaSpec::deserialize(MapAccessDeserializer::new(WithoutSeabed {
            map,
            seabed: &mut seabed,
        }))?;
        Ok(SeaSection {
            sea,
            seabed: seabed.unwrap_or_default(),
        })
    }
}

/// The `[sea]` map as [`SeaSpec`] sees it: `seabed` is taken out (into `seabed`) on the way.
struct WithoutSeabed<'a, A> {
    map: A,
    seabed: &'a mut Option<SeabedSettings>,
}

impl<'de, A: MapAccess<'de>> MapAccess<'de> for WithoutSeabed<'_, A> {
    type Error = A::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> std::result::Result<Option<K::Value>, A::Error> {
        let mut seed = seed;
        loop {
            match self.map.next_key_seed(SeaKey(seed))? {
                None => return Ok(None),
                Some(Ok(key)) => return Ok(Some(key)),
                Some(Err(back)) => {
                    *self.seabed = Some(self.map.next_value()?);
                    seed = back;
                }
            }
        }
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> std::result::Result<V::Value, A::Error> {
        self.map.next_value_seed(seed)
    }
}

/// A key of `[sea]`: `seabed` hands the seed back (`Err`); another key of [`SEA_KEYS`] is
/// given to [`SeaSpec`]'s seed; any other is an unknown field listing [`SEA_KEYS`]. Deserialised
/// through the file's own map, so that errors keep its spans.
struct SeaKey<K>(K);

impl<'de, K: DeserializeSeed<'de>> DeserializeSeed<'de> for SeaKey<K> {
    type Value = std::result::Result<K::Value, K>;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> std::result::Result<Self::Value, D::Error> {
        let key = String::deserialize(d)?;
        if key == "seabed" {
            return Ok(Err(self.0));
        }
        if !SEA_KEYS.contains(&key.as_str()) {
            return Err(de::Error::unknown_field(&key, SEA_KEYS));
        }
        let key: StringDeserializer<D::Error> = key.into_deserializer();
        self.0.deserialize(key).map(Ok)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The section of `[sea]` text (a scene with only that table), or the error after the file.
    fn parse(sea: &str) -> std::result::Result<SeaSection, String> {
        #[derive(Deserialize)]
        struct Only {
            sea: SeaSection,
        }
        let only: Only = toml::from_str(&format!("[sea]\n{sea}")).map_err(|e| e.to_string())?;
        only.sea
            .check_seabed(Path::new("s.toml"))
            .map_err(|e| e.to_string().strip_prefix("s.toml: ").unwrap().to_string())?;
        Ok(only.sea)
    }

    #[test]
    fn sea_keys_are_the_sea_spec_fields_and_seabed() {
        let e = toml::from_str::<SeaSpec>("probe = 1")
            .unwrap_err()
            .to_string();
        let listed: Vec<&str> = e[e.find("expected").unwrap()..]
            .split('`')
            .skip(1)
            .step_by(2)
            .collect();
        assert_eq!(listed, SEA_KEYS[..SEA_KEYS.len() - 1]);
        let e = parse("probe = 1").unwrap_err();
        assert!(
            e.contains("line 2") && e.contains("`waves`, `seabed`"),
            "{e}"
        );
    }

    #[test]
    fn seabed_is_split_off_and_the_rest_is_the_sea() {
        let s =
            parse("depth = 10\n[sea.seabed]\nkbot = 1e5\n[sea.water]\ndensity = 1000\n").unwrap();
        assert_eq!(s.seabed.kbot, 1e5);
        assert_eq!(s.sea.water.density, 1000.0);
        assert_eq!(
            s.sea.depth,
            Some(aqua_env::config::DepthValue::Metres(10.0))
        );
        let e = parse("depth = 10\n[sea.water]\ndensitty = 1000\n").unwrap_err();
        assert!(e.contains("line 4") && e.contains("densitty"), "{e}");
    }

    #[test]
    fn bad_seabed_keys_name_key_value_and_range() {
        let e = parse("depth = 10\n[sea.seabed]\nkbot = -1.0\n").unwrap_err();
        assert_eq!(e, "sea.seabed.kbot = -1: a finite number >= 0");
        let e = parse("depth = 10\n[sea.seabed]\nslip_velocity = 0.0\n").unwrap_err();
        assert_eq!(
            e,
            "sea.seabed.slip_velocity = 0: a velocity in m/s, finite and > 0 (default 0.01)"
        );
        let e = parse("depth = 10\n[sea.seabed]\nfriction_transverse = -0.5\n").unwrap_err();
        assert!(
            e.starts_with("sea.seabed.friction_transverse = -0.5: a friction"),
            "{e}"
        );
        let e = parse("depth = 10\n[sea.seabed]\nkbott = 1.0\n").unwrap_err();
        assert!(e.contains("kbott") && e.contains("kbot"), "{e}");
    }
}
