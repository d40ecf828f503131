//! The one parser of the `kind:key=value,...` specifications (docs/architecture.md, "The
//! application layer"), shared by the CLI, the configurations (an `inhomogeneity` entry given as a
//! spec) and the Python package. Every function takes `what`,
//! the name of the input in the caller's terms (`--profile` on the command line, `profile` in
//! Python), used in its error messages; the library never names a flag itself.

use std::path::Path;

use crate::mdr::{Material, Profile};
use crate::sam::eim::{Axis, Inhomogeneity, Shape};
use crate::sam::indenter::Indenter;
use crate::sam::Body;

/// A specification that does not parse or describes an invalid input; the message names the input
/// (`what`), the specification and the problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct SpecError(pub String);

impl From<crate::mdr::MdrError> for SpecError {
    fn from(e: crate::mdr::MdrError) -> Self {
        Self(e.to_string())
    }
}

impl From<crate::sam::SamError> for SpecError {
    fn from(e: crate::sam::SamError) -> Self {
        Self(e.to_string())
    }
}

impl From<crate::data::DataError> for SpecError {
    fn from(e: crate::data::DataError) -> Self {
        Self(e.to_string())
    }
}

/// `kind:key=value,key=value` → (kind, [(key, value)]). The value list of `table:` is a path.
fn split(spec: &str, what: &str) -> Result<(String, Vec<(String, String)>), SpecError> {
    let (kind, rest) = spec.split_once(':').ok_or_else(|| {
        SpecError(format!(
            "{what} '{spec}': expected KIND:KEY=VALUE,... (e.g. sphere:R=1e-4)"
        ))
    })?;
    let mut pairs: Vec<(String, String)> = Vec::new();
    if kind == "table" {
        return Ok((kind.into(), vec![("file".into(), rest.into())]));
    }
    for item in rest.split(',').filter(|s| !s.trim().is_empty()) {
        let (k, v) = item
            .split_once('=')
            .ok_or_else(|| SpecError(format!("{what} '{spec}': '{item}' is not KEY=VALUE")))?;
        let k = k.trim().to_string();
        if pairs.iter().any(|(p, _)| *p == k) {
            return Err(SpecError(format!("{what} '{spec}': key '{k}' given twice")));
        }
        pairs.push((k, v.trim().to_string()));
    }
    Ok((kind.trim().to_string(), pairs))
}

struct Keys<'a> {
    spec: &'a str,
    what: &'a str,
    pairs: Vec<(String, String)>,
}

impl Keys<'_> {
    fn take(&mut self, key: &str) -> Option<String> {
        let i = self.pairs.iter().position(|(k, _)| k == key)?;
        Some(self.pairs.remove(i).1)
    }

    fn number(&mut self, key: &str) -> Result<f64, SpecError> {
        let v = self.take(key).ok_or_else(|| {
            SpecError(format!(
                "{} '{}': missing key '{key}'",
                self.what, self.spec
            ))
        })?;
        v.parse::<f64>().map_err(|_| {
            SpecError(format!(
                "{} '{}': {key}='{v}' is not a number",
                self.what, self.spec
            ))
        })
    }

    fn positive(&mut self, key: &str) -> Result<f64, SpecError> {
        let v = self.number(key)?;
        if !(v.is_finite() && v > 0.0) {
            return Err(SpecError(format!(
                "{} '{}': {key} must be finite and > 0, got {v}",
                self.what, self.spec
            )));
        }
        Ok(v)
    }

    fn finish(self, allowed: &str) -> Result<(), SpecError> {
        match self.pairs.first() {
            None => Ok(()),
            Some((k, _)) => Err(SpecError(format!(
                "{} '{}': unknown key '{k}' (allowed: {allowed})",
                self.what, self.spec
            ))),
        }
    }
}

/// `sphere:R=..`, `cone:slope=..`, `flat:a=..`, `power:c=..,n=..`, `table:FILE.npy`.
pub fn parse_profile(spec: &str, what: &str) -> Result<Profile, SpecError> {
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    let profile = match kind.as_str() {
        "sphere" => {
            let p = Profile::sphere(keys.number("R")?)?;
            keys.finish("R")?;
            p
        }
        "cone" => {
            let p = Profile::cone(keys.number("slope")?)?;
            keys.finish("slope")?;
            p
        }
        "flat" => {
            let p = Profile::flat_punch(keys.number("a")?)?;
            keys.finish("a")?;
            p
        }
        "power" => {
            let c = keys.number("c")?;
            let n = keys.number("n")?;
            keys.finish("c, n")?;
            Profile::power(c, n)?
        }
        "table" => {
            let file = keys.take("file").unwrap_or_default();
            if file.is_empty() {
                return Err(SpecError(format!(
                    "{what} '{spec}': expected table:FILE.npy"
                )));
            }
            let (r, f) = crate::data::read_profile_table(Path::new(&file))?;
            Profile::tabulated(r, f).map_err(|e| SpecError(format!("{file}: {e}")))?
        }
        other => {
            return Err(SpecError(format!(
                "{what} '{spec}': unknown profile '{other}' (sphere, cone, flat, power, table)"
            )))
        }
    };
    Ok(profile)
}

/// `homogeneous:E=..,nu=..`, `homogeneous:Estar=..`, `graded:E0=..,z0=..,nu=..,k=..`.
pub fn parse_material(spec: &str, what: &str) -> Result<Material, SpecError> {
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    match kind.as_str() {
        "homogeneous" => {
            if keys.pairs.iter().any(|(k, _)| k == "Estar") {
                let m = Material::from_e_star(keys.number("Estar")?)?;
                keys.finish("Estar, or E and nu")?;
                Ok(m)
            } else {
                let e = keys.number("E")?;
                let nu = keys.number("nu")?;
                keys.finish("E, nu (or Estar)")?;
                Ok(Material::homogeneous(e, nu)?)
            }
        }
        "graded" => {
            let e0 = keys.number("E0")?;
            let z0 = keys.number("z0")?;
            let nu = keys.number("nu")?;
            let k = keys.number("k")?;
            keys.finish("E0, z0, nu, k")?;
            Ok(Material::power_law(e0, z0, nu, k)?)
        }
        other => Err(SpecError(format!(
            "{what} '{spec}': unknown material '{other}' (homogeneous, graded)"
        ))),
    }
}

/// The medium of a normalized fretting-wear run (docs/fretting-wear.md, "Graded media"): the
/// grading exponent `k` (0 homogeneous) and, when given, `ν`, which does not enter the normalized
/// run but fixes the physical amplitude scale `u_max = μ (c_N/c_T) d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearMedium {
    /// Grading exponent `k ∈ (−1, 1)`.
    pub k: f64,
    /// Poisson ratio `ν ∈ (−1, 1/2]`, if given.
    pub nu: Option<f64>,
}

impl WearMedium {
    /// `c_T / c_N` (graded tangential MDR constant over the normal one), when `ν` is given.
    pub fn tangential_ratio(&self) -> Option<f64> {
        self.nu
            .and_then(|nu| crate::mdr::tangential::tangential_constant_ratio(self.k, nu).ok())
    }
}

/// `homogeneous` (or `homogeneous:nu=..`) or `graded:k=..,nu=..` for `fretting-wear`: `k ∈ (−1, 1)`,
/// `ν ∈ (−1, 1/2]` (where the graded tangential constant `c_T(k, ν)` is defined). The material
/// specs of `axisym` are read too (`homogeneous:E=..,nu=..`, `graded:E0=..,z0=..,nu=..,k=..`):
/// `E`, `E0`, `z0` set the scales a₀, F₀, N₀ (docs/fretting-wear.md, "Graded media"), not the
/// normalized run, and are checked (> 0) but not used; `Estar` is refused (it gives no ν).
pub fn parse_wear_medium(spec: &str, what: &str) -> Result<WearMedium, SpecError> {
    if spec.trim() == "homogeneous" {
        return Ok(WearMedium { k: 0.0, nu: None });
    }
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    let (k, nu) = match kind.as_str() {
        "homogeneous" => {
            if keys.take("Estar").is_some() {
                return Err(SpecError(format!(
                    "{what} '{spec}': Estar is not used by the normalized run and gives no ν; \
                     give homogeneous:nu=.. or homogeneous"
                )));
            }
            // E sets the scales (a₀, F₀, N₀), not the normalized run: accepted as in `axisym`.
            if keys.pairs.iter().any(|(k, _)| k == "E") {
                keys.positive("E")?;
            }
            let nu = keys.number("nu")?;
            keys.finish("nu (and E, which sets the scales only)")?;
            (0.0, nu)
        }
        "graded" => {
            // E0 and z0 set the scales, not the normalized run: accepted together, as in the
            // material spec of `axisym`.
            let has = |keys: &Keys, key: &str| keys.pairs.iter().any(|(k, _)| k == key);
            match (has(&keys, "E0"), has(&keys, "z0")) {
                (true, true) => {
                    keys.positive("E0")?;
                    keys.positive("z0")?;
                }
                (false, false) => {}
                _ => {
                    return Err(SpecError(format!(
                        "{what} '{spec}': E0 and z0 go together (the material spec of axisym, \
                         E(z) = E0 (z/z0)^k) or not at all (the normalized run needs neither)"
                    )))
                }
            }
            let k = keys.number("k")?;
            let nu = keys.number("nu")?;
            keys.finish("k, nu (and E0, z0, which set the scales only)")?;
            if !(k.is_finite() && k > -1.0 && k < 1.0) {
                return Err(SpecError(format!(
                    "{what} '{spec}': k = {k} must be in (−1, 1) (E ∝ z^k)"
                )));
            }
            (k, nu)
        }
        other => {
            return Err(SpecError(format!(
                "{what} '{spec}': unknown medium '{other}' (homogeneous, graded)"
            )))
        }
    };
    if !(nu.is_finite() && nu > -1.0 && nu <= 0.5) {
        return Err(SpecError(format!(
            "{what} '{spec}': nu = {nu} must be in (−1, 0.5] (the range of the tangential constant c_T(k, ν))"
        )));
    }
    Ok(WearMedium { k, nu: Some(nu) })
}

/// `sphere:x=..,y=..,z=..,r=..,E=..,nu=..`, `cylinder:axis=y,x=..,z=..,r=..,E=..,nu=..` (or
/// `axis=x,y=..`), `cuboid:x=..,y=..,z=..,hx=..,hy=..,hz=..,E=..,nu=..`; `z` is the depth of the
/// centre (m, positive into the body), `hx..` half sizes. Values are checked by the library.
pub fn parse_inhomogeneity(spec: &str, what: &str) -> Result<Inhomogeneity, SpecError> {
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    let shape = match kind.as_str() {
        "sphere" => {
            let s = Shape::Sphere {
                x: keys.number("x")?,
                y: keys.number("y")?,
                z: keys.number("z")?,
                r: keys.number("r")?,
            };
            (s, "x, y, z, r, E, nu")
        }
        "cylinder" => {
            let axis = keys.take("axis").ok_or_else(|| {
                SpecError(format!("{what} '{spec}': missing key 'axis' (x or y)"))
            })?;
            let (axis, position) = match axis.as_str() {
                "y" => (Axis::Y, keys.number("x")?),
                "x" => (Axis::X, keys.number("y")?),
                other => {
                    return Err(SpecError(format!(
                        "{what} '{spec}': axis='{other}' must be x or y (the cylinder lies parallel to the surface)"
                    )))
                }
            };
            let s = Shape::Cylinder {
                axis,
                position,
                z: keys.number("z")?,
                r: keys.number("r")?,
            };
            (s, "axis, x (axis=y) or y (axis=x), z, r, E, nu")
        }
        "cuboid" => {
            let s = Shape::Cuboid {
                x: keys.number("x")?,
                y: keys.number("y")?,
                z: keys.number("z")?,
                half: [keys.number("hx")?, keys.number("hy")?, keys.number("hz")?],
            };
            (s, "x, y, z, hx, hy, hz, E, nu")
        }
        other => {
            return Err(SpecError(format!(
                "{what} '{spec}': unknown inhomogeneity '{other}' (sphere, cylinder, cuboid)"
            )))
        }
    };
    let inh = Inhomogeneity {
        shape: shape.0,
        e: keys.number("E")?,
        nu: keys.number("nu")?,
    };
    keys.finish(shape.1)?;
    inh.validate()
        .map_err(|e| SpecError(format!("{what} '{spec}': {e}")))?;
    Ok(inh)
}

/// `sphere:R=..`, `ellipsoid:Rx=..,Ry=..`, `cone:slope=..`, `flat:a=..`, `table:FILE.npy` (heights
/// on the grid, float64 (N₁, N₂)).
pub fn parse_indenter(spec: &str, what: &str) -> Result<Indenter, SpecError> {
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    let (indenter, allowed) = match kind.as_str() {
        "sphere" => (Indenter::sphere(keys.positive("R")?), "R"),
        "ellipsoid" => (
            Indenter::Ellipsoid {
                rx: keys.positive("Rx")?,
                ry: keys.positive("Ry")?,
            },
            "Rx, Ry",
        ),
        "cone" => (
            Indenter::Cone {
                slope: keys.positive("slope")?,
            },
            "slope",
        ),
        "flat" => (
            Indenter::Flat {
                a: keys.positive("a")?,
            },
            "a",
        ),
        "table" => {
            let file = keys.take("file").unwrap_or_default();
            if file.is_empty() {
                return Err(SpecError(format!(
                    "{what} '{spec}': expected table:FILE.npy"
                )));
            }
            let (n1, n2, heights) = crate::data::read_npy_2d(Path::new(&file))?;
            let ind = Indenter::Table { n1, n2, heights };
            ind.validate()
                .map_err(|e| SpecError(format!("{file}: {e}")))?;
            (ind, "")
        }
        other => {
            return Err(SpecError(format!(
                "{what} '{spec}': unknown indenter '{other}' (sphere, ellipsoid, cone, flat, table)"
            )))
        }
    };
    keys.finish(allowed)?;
    Ok(indenter)
}

/// `rigid` or `homogeneous:E=..,nu=..` (a body of the 3D contact).
pub fn parse_body(spec: &str, what: &str) -> Result<Body, SpecError> {
    if spec.trim() == "rigid" {
        return Ok(Body::Rigid);
    }
    let (kind, pairs) = split(spec, what)?;
    let mut keys = Keys { spec, what, pairs };
    if kind != "homogeneous" {
        return Err(SpecError(format!(
            "{what} '{spec}': use homogeneous:E=..,nu=.. (or rigid)"
        )));
    }
    let e = keys.positive("E")?;
    let nu = keys.number("nu")?;
    keys.finish("E, nu")?;
    Body::elastic(e, nu).map_err(|e| SpecError(format!("{what} '{spec}': {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_errors_name_the_problem() {
        assert!(matches!(
            parse_profile("sphere:R=1e-4", "--profile").unwrap(),
            Profile::Sphere { .. }
        ));
        assert!(matches!(
            parse_profile("power:c=2,n=3", "--profile").unwrap(),
            Profile::Power { .. }
        ));
        let e = parse_profile("sphere:R=1,Q=2", "--profile")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown key 'Q'"), "{e}");
        let e = parse_profile("sphere:R=abc", "--profile")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a number"), "{e}");
        let e = parse_profile("sphere", "--profile")
            .unwrap_err()
            .to_string();
        assert!(e.contains("KIND:KEY=VALUE"), "{e}");
        let e = parse_material("homogeneous:E=1e9", "--material")
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing key 'nu'"), "{e}");
        assert!(parse_material("homogeneous:Estar=1e9", "--material").is_ok());
        assert!(parse_material("homogeneous:E=1e9,nu=0.6", "--material").is_err());
        let m = parse_material("graded:E0=2e11,z0=1e-6,nu=0.3,k=0.5", "--material").unwrap();
        assert_eq!(m.grading_exponent(), 0.5);
        let e = parse_material("graded:E0=2e11,z0=1e-6,nu=0.3,k=1", "--material")
            .unwrap_err()
            .to_string();
        assert!(e.contains("grading exponent k"), "{e}");
        let e = parse_material("graded:E0=2e11,nu=0.3,k=0.5", "--material")
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing key 'z0'"), "{e}");
        let e = parse_indenter("sphere:R=-1", "indenter")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("indenter 'sphere:R=-1': R must be finite and > 0"),
            "{e}"
        );
        assert_eq!(
            parse_indenter("ellipsoid:Rx=1,Ry=2", "--indenter").unwrap(),
            Indenter::Ellipsoid { rx: 1.0, ry: 2.0 }
        );
        assert!(matches!(parse_body("rigid", "--material"), Ok(Body::Rigid)));
        let e = parse_body("homogeneous:E=1e9", "material")
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing key 'nu'"), "{e}");
    }
}
