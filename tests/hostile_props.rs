//! Properties over hostile specification strings and configuration fields (issue 19): whatever
//! the text, the one parser (`halfspace::spec`) and the configuration schema (`halfspace::config`)
//! return a value or a typed error whose message names the input — they never panic, and a
//! configuration they accept is estimated and checked before anything is allocated.

use halfspace::config::{map_config_from_toml, LoopConfig};
use halfspace::spec::{
    parse_body, parse_indenter, parse_inhomogeneity, parse_material, parse_profile,
    parse_wear_medium,
};
use proptest::prelude::*;

/// Values a careless or hostile user types.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e400".to_string()),
        Just("-1e400".to_string()),
        Just("5e-324".to_string()),
        Just("1e-310".to_string()),
        Just("0".to_string()),
        Just("-0".to_string()),
        Just("".to_string()),
        Just("abc".to_string()),
        Just("1,2".to_string()),
        Just("0x10".to_string()),
        Just("y".to_string()),
        Just("x".to_string()),
        (-1e12f64..1e12).prop_map(|v| format!("{v:e}")),
        (-2.0f64..2.0).prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| v.to_string()),
        "[ -~]{0,12}",
    ]
}

fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("R"),
        Just("Rx"),
        Just("Ry"),
        Just("slope"),
        Just("a"),
        Just("c"),
        Just("n"),
        Just("E"),
        Just("nu"),
        Just("Estar"),
        Just("E0"),
        Just("z0"),
        Just("k"),
        Just("x"),
        Just("y"),
        Just("z"),
        Just("r"),
        Just("axis"),
        Just("hx"),
        Just("hy"),
        Just("hz"),
        Just("file"),
        Just(""),
        Just("="),
        Just("R "),
    ]
    .prop_map(str::to_string)
}

fn kind() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("sphere"),
        Just("cone"),
        Just("flat"),
        Just("power"),
        Just("ellipsoid"),
        Just("homogeneous"),
        Just("graded"),
        Just("rigid"),
        Just("cylinder"),
        Just("cuboid"),
        Just(""),
        Just("sphere "),
        Just("SPHERE"),
        Just("table"),
    ]
    .prop_map(str::to_string)
}

fn spec() -> impl Strategy<Value = String> {
    (
        kind(),
        proptest::collection::vec((key(), value()), 0..9),
        any::<bool>(),
    )
        .prop_map(|(kind, pairs, colon)| {
            // `table:` would read a file named by the rest: keep the property about parsing.
            let kind = if kind == "table" {
                "tablet".into()
            } else {
                kind
            };
            let body: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={v}")).collect();
            if colon {
                format!("{kind}:{}", body.join(","))
            } else {
                format!("{kind}{}", body.join(","))
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn spec_strings_never_panic_and_errors_name_the_input(s in spec()) {
        let checks: [(&str, Option<String>); 6] = [
            ("--profile", parse_profile(&s, "--profile").err().map(|e| e.to_string())),
            ("--material", parse_material(&s, "--material").err().map(|e| e.to_string())),
            ("--indenter", parse_indenter(&s, "--indenter").err().map(|e| e.to_string())),
            ("--indenter-material", parse_body(&s, "--indenter-material").err().map(|e| e.to_string())),
            ("--inhomogeneity", parse_inhomogeneity(&s, "--inhomogeneity").err().map(|e| e.to_string())),
            ("--material", parse_wear_medium(&s, "--material").err().map(|e| e.to_string())),
        ];
        for (what, err) in checks {
            if let Some(message) = err {
                prop_assert!(!message.is_empty());
                prop_assert!(!message.contains('\n'), "one line: {message}");
                // The parser's own messages name the input; the library's name the parameter.
                prop_assert!(
                    message.contains(what) || message.contains("must be") || message.contains("got"),
                    "{what}: {message}"
                );
            }
        }
    }
}

/// TOML values for the fretting-loop keys.
fn toml_value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e-320".to_string()),
        Just("1e300".to_string()),
        Just("9223372036854775807".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("\"abc\"".to_string()),
        Just("\"gap-centred\"".to_string()),
        Just("[]".to_string()),
        Just("true".to_string()),
        (1u64..100_000).prop_map(|v| v.to_string()),
        (-1e3f64..1e3).prop_map(|v| format!("{v:e}")),
        (1e-12f64..1e-3).prop_map(|v| format!("{v:e}")),
    ]
}

fn config_key() -> impl Strategy<Value = &'static str> {
    prop_oneof![
        Just("radius"),
        Just("e"),
        Just("nu"),
        Just("friction"),
        Just("force"),
        Just("normal_steps"),
        Just("amplitude"),
        Just("shift_step"),
        Just("grid"),
        Just("extent_over_a"),
        Just("layout"),
        Just("fibre_e_ratio"),
        Just("subsurface_over_a"),
        Just("unknown_key"),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn loop_configs_never_panic_and_accepted_ones_are_estimated(
        fields in proptest::collection::btree_map(config_key(), toml_value(), 0..6),
        composite in any::<bool>(),
        loads in proptest::collection::vec(toml_value(), 0..4),
    ) {
        let text: String = fields.iter().map(|(k, v)| format!("{k} = {v}\n")).collect();
        match toml::from_str::<LoopConfig>(&text) {
            Err(e) => prop_assert!(!e.message().is_empty()),
            Ok(cfg) => {
                let preset = if composite { "composite" } else { "homogeneous" };
                match cfg.case(preset, None) {
                    Err(e) => prop_assert!(!e.to_string().contains('\n'), "{e}"),
                    Ok(case) => {
                        // Accepted: the scales are normal numbers and the estimate is finite.
                        prop_assert!(case.hertz_radius().is_normal());
                        let est = case.estimate();
                        prop_assert!(est.increments >= 1.0 && !est.bytes.is_nan());
                        let _ = est.check("the fretting loop");
                    }
                }
            }
        }
        let map_text = format!(
            "{text}[map]\nloads = [{}]\namplitudes = [4e-8]\n",
            loads.join(",")
        );
        if let Ok((cfg, axes)) = map_config_from_toml(&map_text, "--config map.toml") {
            if let Err(e) = cfg.map("homogeneous", None, axes.loads, axes.amplitudes) {
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }
}

/// The largest grid the configuration takes is estimated (and refused by the estimate) without a
/// panic: the contact window's cell count is multiplied in `f64` (a `usize` product overflowed
/// for `grid = 2⁶³ − 1`, found by the property above in CI, stop 48).
#[test]
fn the_largest_grid_is_estimated_without_overflow() {
    let cfg: LoopConfig = toml::from_str("grid = 9223372036854775807\n").unwrap();
    let case = cfg.case("homogeneous", None).unwrap();
    assert!(case.contact_window().unwrap().is_some());
    let est = case.estimate();
    assert!(est.bytes.is_finite() && est.bytes > 1e30, "{}", est.bytes);
    assert!(est.check("the fretting loop").is_err());
}
