//! Our EXRs read by a third-party reader (issue 29): the OpenEXR project's own Python bindings
//! (and OpenImageIO where installed) through scripts/check_exr.py, on files the binary wrote (a
//! render of the furnace, whose exact image is known, an experiment run's image and its cached
//! reference) and on a library-written image with NaN, infinities and -0.0. Channels, size,
//! every sample's bits and the wavetrace.* attributes must match; a damaged file and a wrong
//! expectation must fail the same check.
//!
//! Needs `WAVETRACE_EXR_PYTHON`, a Python with `OpenEXR` and `numpy` (scripts/test.sh makes one
//! with scripts/exr_reader.sh); without it the check is listed as skipped, never passed silently.

use crate::experiment::{scratch, small_config, wavetrace, write_config};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{json, Value};
use wavetrace::image_io::{read_exr, write_exr, RgbImage};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn python() -> Option<PathBuf> {
    crate::common::third_party_python("EXRs read by a third-party reader")
}

fn check_exr(py: &Path, pairs: &[(PathBuf, PathBuf)]) -> Output {
    let mut cmd = Command::new(py);
    cmd.arg(crate::common::root().join("scripts/check_exr.py"));
    for (exr, expected) in pairs {
        cmd.arg(exr).arg(expected);
    }
    cmd.output().expect("run scripts/check_exr.py")
}

/// EXPECTED.json for `exr`: the given pixels' bits and attributes, plus `extra` fields.
fn expect(exr: &Path, image: &RgbImage, attributes: &[(String, String)], extra: Value) -> PathBuf {
    let mut expected = json!({
        "width": image.width,
        "height": image.height,
        "rgb_f32_bits": image.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        "attributes": attributes.iter().map(|(k, v)| (k.clone(), Value::String(v.clone()))).collect::<serde_json::Map<_, _>>(),
    });
    if let (Value::Object(e), Value::Object(x)) = (&mut expected, extra) {
        e.extend(x);
    }
    let path = exr.with_extension("expected.json");
    std::fs::write(&path, serde_json::to_string(&expected).unwrap()).unwrap();
    path
}

fn attribute<'a>(attrs: &'a [(String, String)], name: &str) -> &'a str {
    attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str()).unwrap_or_else(|| panic!("no {name}"))
}

/// The furnace render's exact image: 0.5 where a pixel lies wholly on the sphere (albedo 0.5
/// under white light), 1 where it misses it, between only on the silhouette.
#[test]
fn binary_written_exrs_read_the_same_in_openexr() {
    let Some(py) = python() else { return };
    let dir = scratch("exr-third-party");

    let furnace = dir.join("furnace.exr");
    let o = wavetrace(&[
        "render",
        "--scene",
        "furnace",
        "--method",
        "cpu",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "4",
        "--seed",
        "3",
        "--out",
        s(&furnace),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (image, attrs) = read_exr(&furnace).unwrap();
    // What the third party is asked to confirm is what the render was asked for.
    for (k, v) in [
        ("wavetrace.scene", "furnace"),
        ("wavetrace.method", "cpu"),
        ("wavetrace.spp", "4"),
        ("wavetrace.seed", "3"),
        ("wavetrace.max_depth", "50"),
        ("wavetrace.nee", "off"),
    ] {
        assert_eq!(attribute(&attrs, k), v, "{k}");
    }
    assert!(!attribute(&attrs, "wavetrace.git_commit").is_empty());
    let furnace_expected = expect(&furnace, &image, &attrs, json!({"values_in": [0.5, 1.0]}));

    // An experiment run's image and its cached reference.
    let mut config = small_config(json!([{"method": "cpu"}]));
    config["resolutions"] = json!(["16x9"]);
    config["spp"] = json!([2]);
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"] = json!({"method": "cpu-f64", "spp": 4});
    let config = write_config(&dir, "exr", &config);
    let (out, cache) = (dir.join("out"), dir.join("cache"));
    let o = wavetrace(&["experiment", "run", s(&config), "--out", s(&out), "--cache", s(&cache)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = wavetrace::experiment::ExperimentReport::read(&out).unwrap();
    let run_exr = out.join(&report.runs[0].images.as_ref().unwrap().exr);
    let ref_exr = PathBuf::from(&report.references[0].exr);
    let mut pairs = vec![(furnace.clone(), furnace_expected.clone())];
    for (exr, method, spp) in [(&run_exr, "cpu", "2"), (&ref_exr, "cpu-f64", "4")] {
        let (image, attrs) = read_exr(exr).unwrap();
        assert_eq!((image.width, image.height), (16, 9));
        assert_eq!(
            (attribute(&attrs, "wavetrace.method"), attribute(&attrs, "wavetrace.spp")),
            (method, spp)
        );
        pairs.push((exr.clone(), expect(exr, &image, &attrs, json!({}))));
    }
    let o = check_exr(&py, &pairs);
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "the third-party reader disagrees:\n{stdout}{stderr}");
    assert!(stdout.matches("bit-identical").count() >= 3, "{stdout}");
    assert!(stdout.contains("OpenEXR 3."), "{stdout}");

    // Negative controls: the same check fails on a truncated file, a sample one ulp off, a
    // channel-swapped expectation, a wrong attribute and a render that is not the furnace's.
    let truncated = dir.join("truncated.exr");
    let bytes = std::fs::read(&furnace).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let mut wrong: Vec<(&str, PathBuf, PathBuf, &str)> =
        vec![("truncated", truncated, furnace_expected.clone(), "cannot read")];
    let edit = |name: &str, change: &dyn Fn(&mut Value)| {
        let mut e: Value =
            serde_json::from_str(&std::fs::read_to_string(&furnace_expected).unwrap()).unwrap();
        change(&mut e);
        let path = dir.join(format!("{name}.expected.json"));
        std::fs::write(&path, e.to_string()).unwrap();
        path
    };
    let ulp = edit("ulp", &|e| {
        let bits = e["rgb_f32_bits"][100].as_u64().unwrap();
        e["rgb_f32_bits"][100] = (bits + 1).into();
    });
    wrong.push(("one ulp", furnace.clone(), ulp, "samples differ"));
    let (w, h) = (image.width as usize, image.height as usize);
    let flipped = edit("flipped", &|e| {
        let bits: Vec<Value> = e["rgb_f32_bits"].as_array().unwrap().clone();
        let rows: Vec<Value> = bits.chunks(3 * w).rev().flatten().cloned().collect();
        assert_eq!(rows.len(), 3 * w * h);
        e["rgb_f32_bits"] = rows.into();
    });
    wrong.push(("upside down", furnace.clone(), flipped, "samples differ"));
    let attr = edit("attribute", &|e| e["attributes"]["wavetrace.spp"] = "5".into());
    wrong.push(("attribute", furnace.clone(), attr, "attribute wavetrace.spp"));
    let (run_image, run_attrs) = read_exr(&run_exr).unwrap();
    let not_furnace = expect(&run_exr, &run_image, &run_attrs, json!({"values_in": [0.5, 1.0]}));
    wrong.push(("not the furnace", run_exr.clone(), not_furnace, "outside [0.5, 1.0]"));
    for (what, exr, expected, needle) in wrong {
        let o = check_exr(&py, &[(exr, expected)]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{what}: the check passed");
        assert!(stderr.contains(needle) && stderr.contains("MISMATCH"), "{what}: {stderr}");
    }
}

/// A library-written image that pins orientation and channel order (every sample distinct) and
/// holds the values a careless reader mangles (NaN, ±infinity, -0.0, subnormals), with Unicode
/// in an attribute: the third party reads the bits we wrote, compared with the image in memory,
/// not with our reader.
#[test]
fn exact_samples_and_unicode_attributes_read_the_same_in_openexr() {
    let Some(py) = python() else { return };
    let dir = scratch("exr-third-party-exact");
    let (w, h) = (7u32, 5u32);
    let mut data: Vec<f32> = (0..w * h * 3).map(|i| i as f32 * 0.25 + 0.125).collect();
    data[..6].copy_from_slice(&[
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -0.0,
        f32::MIN_POSITIVE / 4.0,
        f32::MAX,
    ]);
    let image = RgbImage::from_data(w, h, data).unwrap();
    let attributes: Vec<(String, String)> =
        [("wavetrace.method", "megakernel"), ("wavetrace.scene", "cornell ✓ <&>"), ("wavetrace.spp", "64")]
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
    let exr = dir.join("exact.exr");
    write_exr(&exr, &image, &attributes).unwrap();
    let expected = expect(&exr, &image, &attributes, json!({}));
    let o = check_exr(&py, &[(exr, expected)]);
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}
