//! Parsing of `kind:key=value,...` specifications (design.md, CLI contract).

use std::path::Path;

use halfspace::mdr::{Material, Profile};
use halfspace::sam::eim::{Axis, Inhomogeneity, Shape};

use super::CliError;

/// `kind:key=value,key=value` → (kind, [(key, value)]). The value list of `table:` is a path.
fn split(spec: &str, what: &str) -> Result<(String, Vec<(String, String)>), CliError> {
    let (kind, rest) = spec.split_once(':').ok_or_else(|| {
        CliError::Spec(format!(
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
            .ok_or_else(|| CliError::Spec(format!("{what} '{spec}': '{item}' is not KEY=VALUE")))?;
        let k = k.trim().to_string();
        if pairs.iter().any(|(p, _)| *p == k) {
            return Err(CliError::Spec(format!(
                "{what} '{spec}': key '{k}' given twice"
            )));
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

    fn number(&mut self, key: &str) -> Result<f64, CliError> {
        let v = self.take(key).ok_or_else(|| {
            CliError::Spec(format!(
                "{} '{}': missing key '{key}'",
                self.what, self.spec
            ))
        })?;
        v.parse::<f64>().map_err(|_| {
            CliError::Spec(format!(
                "{} '{}': {key}='{v}' is not a number",
                self.what, self.spec
            ))
        })
    }

    fn finish(self, allowed: &str) -> Result<(), CliError> {
        match self.pairs.first() {
            None => Ok(()),
            Some((k, _)) => Err(CliError::Spec(format!(
                "{} '{}': unknown key '{k}' (allowed: {allowed})",
                self.what, self.spec
            ))),
        }
    }
}

/// `sphere:R=..`, `cone:slope=..`, `flat:a=..`, `power:c=..,n=..`, `table:FILE.npy`.
pub fn parse_profile(spec: &str) -> Result<Profile, CliError> {
    let what = "--profile";
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
                return Err(CliError::Spec(format!(
                    "{what} '{spec}': expected table:FILE.npy"
                )));
            }
            let (r, f) = halfspace::data::read_profile_table(Path::new(&file))?;
            Profile::tabulated(r, f).map_err(|e| CliError::Spec(format!("{file}: {e}")))?
        }
        other => {
            return Err(CliError::Spec(format!(
                "{what} '{spec}': unknown profile '{other}' (sphere, cone, flat, power, table)"
            )))
        }
    };
    Ok(profile)
}

/// `homogeneous:E=..,nu=..`, `homogeneous:Estar=..`, `graded:E0=..,z0=..,nu=..,k=..`.
pub fn parse_material(spec: &str) -> Result<Material, CliError> {
    let what = "--material";
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
        other => Err(CliError::Spec(format!(
            "{what} '{spec}': unknown material '{other}' (homogeneous, graded)"
        ))),
    }
}

/// `sphere:x=..,y=..,z=..,r=..,E=..,nu=..`, `cylinder:axis=y,x=..,z=..,r=..,E=..,nu=..` (or
/// `axis=x,y=..`), `cuboid:x=..,y=..,z=..,hx=..,hy=..,hz=..,E=..,nu=..`; `z` is the depth of the
/// centre (m, positive into the body), `hx..` half sizes. Values are checked by the library.
pub fn parse_inhomogeneity(spec: &str) -> Result<Inhomogeneity, CliError> {
    let what = "--inhomogeneity";
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
                CliError::Spec(format!("{what} '{spec}': missing key 'axis' (x or y)"))
            })?;
            let (axis, position) = match axis.as_str() {
                "y" => (Axis::Y, keys.number("x")?),
                "x" => (Axis::X, keys.number("y")?),
                other => {
                    return Err(CliError::Spec(format!(
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
            return Err(CliError::Spec(format!(
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
        .map_err(|e| CliError::Spec(format!("{what} '{spec}': {e}")))?;
    Ok(inh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_errors_name_the_problem() {
        assert!(matches!(
            parse_profile("sphere:R=1e-4").unwrap(),
            Profile::Sphere { .. }
        ));
        assert!(matches!(
            parse_profile("power:c=2,n=3").unwrap(),
            Profile::Power { .. }
        ));
        let e = parse_profile("sphere:R=1,Q=2").unwrap_err().to_string();
        assert!(e.contains("unknown key 'Q'"), "{e}");
        let e = parse_profile("sphere:R=abc").unwrap_err().to_string();
        assert!(e.contains("not a number"), "{e}");
        let e = parse_profile("sphere").unwrap_err().to_string();
        assert!(e.contains("KIND:KEY=VALUE"), "{e}");
        let e = parse_material("homogeneous:E=1e9").unwrap_err().to_string();
        assert!(e.contains("missing key 'nu'"), "{e}");
        assert!(parse_material("homogeneous:Estar=1e9").is_ok());
        assert!(parse_material("homogeneous:E=1e9,nu=0.6").is_err());
        let m = parse_material("graded:E0=2e11,z0=1e-6,nu=0.3,k=0.5").unwrap();
        assert_eq!(m.grading_exponent(), 0.5);
        let e = parse_material("graded:E0=2e11,z0=1e-6,nu=0.3,k=1")
            .unwrap_err()
            .to_string();
        assert!(e.contains("grading exponent k"), "{e}");
        let e = parse_material("graded:E0=2e11,nu=0.3,k=0.5")
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing key 'z0'"), "{e}");
    }
}
