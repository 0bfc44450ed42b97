//! A sea description changed by plain parameters (the flags of `aqua waves`): each given value
//! replaces the corresponding key of a [`SeaSpec`] (docs/theory/waves.md).

use crate::Stretching;
use crate::config::{
    CurrentKind, DepthValue, GammaValue, SeaSpec, SpectrumShape, SpectrumSpec, WaveKind,
};

/// The enum value a scene word spells (`airy` for [`WaveKind`], `wheeler` for
/// [`Stretching`], `pm` for [`SpectrumShape`]); `None` for a word the key does not take.
pub fn from_name<T: serde::de::DeserializeOwned>(name: &str) -> Option<T> {
    use serde::de::{IntoDeserializer, value::Error};
    T::deserialize(IntoDeserializer::<Error>::into_deserializer(name)).ok()
}

/// Values that replace keys of a [`SeaSpec`]; `None` keeps the key as it is.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SeaParams {
    /// Water depth h: metres, or a word such as "infinite" (`sea.depth`).
    pub depth: Option<String>,
    /// Gravity g [m/s²].
    pub gravity: Option<f64>,
    /// Uniform current velocity [m/s].
    pub current: Option<[f64; 3]>,
    /// Wave kind.
    pub kind: Option<WaveKind>,
    /// Surface stretching.
    pub stretching: Option<Stretching>,
    /// Wave ramp duration [s].
    pub ramp_time: Option<f64>,
    /// Regular wave height H [m].
    pub height: Option<f64>,
    /// Regular wave period T [s].
    pub period: Option<f64>,
    /// Travel direction [deg] (regular waves; mean direction of an irregular sea).
    pub direction: Option<f64>,
    /// Significant wave height Hs [m] (irregular).
    pub hs: Option<f64>,
    /// Peak period Tp [s] (irregular).
    pub tp: Option<f64>,
    /// Spectrum shape (irregular).
    pub spectrum: Option<SpectrumShape>,
    /// JONSWAP γ: a number or a word such as "auto" (irregular).
    pub gamma: Option<String>,
    /// Number of components (irregular).
    pub components: Option<usize>,
    /// Seed of the random phases (irregular).
    pub seed: Option<u64>,
    /// cos-2s spreading exponent (irregular).
    pub spreading: Option<f64>,
}

/// Spectrum parameters given for a sea that is not irregular.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "spectrum parameters (Hs, Tp, shape, gamma, components, seed, spreading) need an irregular sea"
)]
pub struct SpectrumWithoutIrregular;

impl SeaParams {
    /// Whether any spectrum parameter is given.
    pub fn has_spectrum(&self) -> bool {
        self.hs.is_some()
            || self.tp.is_some()
            || self.spectrum.is_some()
            || self.gamma.is_some()
            || self.components.is_some()
            || self.seed.is_some()
            || self.spreading.is_some()
    }

    /// `spec` with the given values in place; a current becomes uniform. The direction goes to
    /// the spectrum of an irregular sea, else to the regular wave.
    pub fn apply(&self, mut spec: SeaSpec) -> Result<SeaSpec, SpectrumWithoutIrregular> {
        if let Some(d) = &self.depth {
            spec.depth = Some(match d.parse::<f64>() {
                Ok(h) => DepthValue::Metres(h),
                Err(_) => DepthValue::Word(d.clone()),
            });
        }
        if let Some(g) = self.gravity {
            spec.gravity = g;
        }
        if let Some(c) = self.current {
            spec.current.kind = CurrentKind::Uniform;
            spec.current.velocity = Some(c);
        }
        let w = &mut spec.waves;
        if let Some(k) = self.kind {
            w.kind = k;
        }
        if let Some(s) = self.stretching {
            w.stretching = Some(s);
        }
        if let Some(r) = self.ramp_time {
            w.ramp_time = r;
        }
        if w.kind == WaveKind::Irregular || self.has_spectrum() {
            if w.kind != WaveKind::Irregular {
                return Err(SpectrumWithoutIrregular);
            }
            let sp = w.spectrum.get_or_insert_with(SpectrumSpec::default);
            if let Some(v) = self.hs {
                sp.hs = Some(v);
            }
            if let Some(v) = self.tp {
                sp.tp = Some(v);
            }
            if let Some(s) = self.spectrum {
                sp.shape = s;
            }
            if let Some(g) = &self.gamma {
                sp.gamma = Some(match g.parse::<f64>() {
                    Ok(v) => GammaValue::Number(v),
                    Err(_) => GammaValue::Word(g.clone()),
                });
            }
            if let Some(n) = self.components {
                sp.components = n;
            }
            if let Some(s) = self.seed {
                sp.seed = s;
            }
            if let Some(s) = self.spreading {
                sp.spreading_s = Some(s);
            }
            if let Some(d) = self.direction {
                sp.mean_direction = d;
            }
        } else {
            if let Some(h) = self.height {
                w.height = Some(h);
            }
            if let Some(t) = self.period {
                w.period = Some(t);
            }
            if let Some(d) = self.direction {
                w.direction = d;
            }
        }
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BuildOptions;

    #[test]
    fn scene_words_name_their_values() {
        assert_eq!(from_name::<WaveKind>("stokes2"), Some(WaveKind::Stokes2));
        assert_eq!(
            from_name::<Stretching>("wheeler"),
            Some(Stretching::Wheeler)
        );
        assert_eq!(from_name::<SpectrumShape>("pm"), Some(SpectrumShape::Pm));
        assert_eq!(from_name::<WaveKind>("stokes3"), None);
    }

    /// Airy wave H = 2 m, T = 8 s in deep water: the built sea has ω = 2π/T and, from the
    /// deep-water dispersion relation ω² = g·k, L = g·T²/(2π).
    #[test]
    fn airy_parameters_build_the_deep_water_wave() {
        let p = SeaParams {
            kind: Some(WaveKind::Airy),
            height: Some(2.0),
            period: Some(8.0),
            depth: Some("infinite".into()),
            direction: Some(30.0),
            ..Default::default()
        };
        let spec = p.apply(SeaSpec::default()).unwrap();
        assert_eq!(spec.waves.height, Some(2.0));
        assert_eq!(spec.waves.direction, 30.0);
        let (_, s) = spec.build(&BuildOptions::default()).unwrap();
        let r = &s.regular[0];
        let t: f64 = 8.0;
        let l = s.gravity * t * t / (2.0 * std::f64::consts::PI);
        assert!((r.period - t).abs() < 1e-12 && (r.height - 2.0).abs() < 1e-12);
        assert!(
            (r.wavelength - l).abs() < 1e-9 * l,
            "{} vs {l}",
            r.wavelength
        );
        assert!((r.direction_deg - 30.0).abs() < 1e-12);
    }

    #[test]
    fn spectrum_parameters_need_an_irregular_sea() {
        let p = SeaParams {
            kind: Some(WaveKind::Airy),
            hs: Some(2.0),
            ..Default::default()
        };
        assert_eq!(p.apply(SeaSpec::default()), Err(SpectrumWithoutIrregular));
        let p = SeaParams {
            kind: Some(WaveKind::Irregular),
            hs: Some(2.0),
            direction: Some(15.0),
            current: Some([0.5, 0.0, 0.0]),
            ..Default::default()
        };
        let spec = p.apply(SeaSpec::default()).unwrap();
        let sp = spec.waves.spectrum.unwrap();
        assert_eq!((sp.hs, sp.mean_direction), (Some(2.0), 15.0));
        assert_eq!(spec.current.kind, CurrentKind::Uniform);
        assert_eq!(spec.waves.direction, SeaSpec::default().waves.direction);
    }
}
