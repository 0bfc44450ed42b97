//! The grids of the coefficient tables (`aqua coeffs`): inflow angles θ [deg] from
//! "start:stop:step" or a list, Reynolds numbers from "lo:hi:n" (log-spaced) or a list
//! (docs/theory/hydrodynamics.md#screen-models, #morison-coefficients).

/// A grid text that is not a valid grid; the message names the key, the text and what is valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct GridError(pub String);

fn number(key: &str, s: &str) -> Result<f64, GridError> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| GridError(format!("{key}: \"{s}\" is not a finite number")))
}

/// Angles θ [deg] from "a:b:step" or "a,b,c", each in [0, 90]; `key` names the setting in
/// the error (e.g. `--angles`).
pub fn parse_angles(key: &str, s: &str) -> Result<Vec<f64>, GridError> {
    let out = if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(GridError(format!(
                "{key} = \"{s}\": use start:stop:step in degrees (e.g. 0:90:15) or a list 0,30,60"
            )));
        }
        let (a, b, st) = (
            number(key, parts[0])?,
            number(key, parts[1])?,
            number(key, parts[2])?,
        );
        if !(st > 0.0) || b < a {
            return Err(GridError(format!(
                "{key} = \"{s}\": need start <= stop and step > 0 (e.g. 0:90:15)"
            )));
        }
        let n = ((b - a) / st + 1e-9).floor() as usize;
        if n > 100_000 {
            return Err(GridError(format!(
                "{key} = \"{s}\": too many angles (step too small)"
            )));
        }
        (0..=n).map(|i| a + i as f64 * st).collect::<Vec<_>>()
    } else {
        s.split(',')
            .map(|p| number(key, p))
            .collect::<Result<Vec<_>, _>>()?
    };
    if let Some(bad) = out.iter().find(|a| !(0.0..=90.0).contains(*a)) {
        return Err(GridError(format!(
            "{key}: {bad} deg is outside 0-90 (θ = 0 is flow normal to the net, 90 flow in its plane)"
        )));
    }
    Ok(out)
}

/// Reynolds numbers from a list or "lo:hi:n" (n values log-spaced from lo to hi), each > 0;
/// `key` names the setting in the error (e.g. `--reynolds`).
pub fn parse_reynolds(key: &str, s: &str) -> Result<Vec<f64>, GridError> {
    let out = if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(GridError(format!(
                "{key} = \"{s}\": use lo:hi:n (n log-spaced values) or a list 1,10,100"
            )));
        }
        let (lo, hi) = (number(key, parts[0])?, number(key, parts[1])?);
        let n: usize = parts[2]
            .trim()
            .parse()
            .map_err(|_| GridError(format!("{key} = \"{s}\": n must be a whole number >= 2")))?;
        if !(lo > 0.0 && hi > lo) || !(2..=100_000).contains(&n) {
            return Err(GridError(format!(
                "{key} = \"{s}\": need 0 < lo < hi and 2 <= n <= 100000"
            )));
        }
        let (a, b) = (lo.log10(), hi.log10());
        (0..n)
            .map(|i| 10f64.powf(a + (b - a) * i as f64 / (n - 1) as f64))
            .collect()
    } else {
        s.split(',')
            .map(|p| number(key, p))
            .collect::<Result<Vec<_>, _>>()?
    };
    if let Some(bad) = out.iter().find(|r| !(**r > 0.0)) {
        return Err(GridError(format!("{key}: {bad} must be > 0")));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_range_includes_both_ends() {
        // 0, 15, …, 90: (90 − 0)/15 + 1 = 7 angles.
        let a = parse_angles("--angles", "0:90:15").unwrap();
        assert_eq!(a, vec![0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]);
        // A step that does not divide the range stops below the end.
        assert_eq!(parse_angles("k", "0:90:40").unwrap(), vec![0.0, 40.0, 80.0]);
        assert_eq!(parse_angles("k", "10, 20").unwrap(), vec![10.0, 20.0]);
    }

    #[test]
    fn bad_angles_name_the_key() {
        for s in ["a:b:c", "0:90", "90:0:15", "0:90:0", "95", "0,nan"] {
            let e = parse_angles("--angles", s).unwrap_err();
            assert!(e.0.starts_with("--angles"), "{s}: {e}");
        }
    }

    #[test]
    fn reynolds_range_is_log_spaced() {
        // 1 to 1e6 in 7 values: one per decade.
        let r = parse_reynolds("--reynolds", "1:1e6:7").unwrap();
        assert_eq!(r.len(), 7);
        for (i, v) in r.iter().enumerate() {
            let want = 10f64.powi(i as i32);
            assert!((v / want - 1.0).abs() < 1e-12, "{i}: {v} vs {want}");
        }
        assert_eq!(parse_reynolds("k", "0.5,1e4").unwrap(), vec![0.5, 1e4]);
        for s in ["0,10", "5:1:3", "1:10:1", "1:10:x", "1:10"] {
            assert!(parse_reynolds("--reynolds", s).is_err(), "{s}");
        }
    }
}
