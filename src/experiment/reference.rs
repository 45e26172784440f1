//! Reference images: read from EXRs the config names, or rendered once and cached on disk under a
//! key made of the scene's exact text, the size and how the reference is made (settings, method,
//! and its knobs where away from their defaults), so reruns and other shards sharing the cache
//! directory reuse it. With `"spp": "match"` there is one reference per run's settings (spp,
//! depth, NEE, seed, light knobs), each cached alike.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::cache_lock;
use super::config::{ExperimentConfig, ReferenceSamples, ReferenceSpec};
use super::gpu_slot::GpuSlot;
use super::plan::file_safe;
use super::report::ReferenceRecord;
use crate::image_io::{self, RgbImage};
use crate::light_options::LightOptions;
use crate::method;
use crate::numerics::NumericOptions;
use crate::options::{Method, MethodOptions};
use crate::progress::Progress;
use crate::report::RunReport;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// A loaded reference and its record.
pub struct Reference {
    pub image: RgbImage,
    pub record: ReferenceRecord,
}

/// The references met so far, by cache key (rendered) or scene and size (EXRs).
pub struct References {
    cache_dir: PathBuf,
    loaded: BTreeMap<String, Reference>,
}

impl References {
    pub fn new(cache_dir: PathBuf) -> Self {
        Self { cache_dir, loaded: BTreeMap::new() }
    }

    /// The reference of a run of `scene` with `run` settings and `options` (the config says
    /// which: one per scene and size, or with `"spp": "match"` one per run's settings), loading
    /// or rendering it on first use; `None` when the config has no reference. `out_dir` receives
    /// its PNG preview.
    pub fn get(
        &mut self,
        config: &ExperimentConfig,
        scene: &Scene,
        run: &RenderSettings,
        options: &MethodOptions,
        gpu: &mut GpuSlot,
        out_dir: &Path,
    ) -> Result<Option<&Reference>> {
        let Some(spec) = &config.reference else { return Ok(None) };
        let (width, height) = (run.width, run.height);
        let rendered = spec.render_for(run, options);
        let key = match &rendered {
            Some((method, settings, o)) => cache_key(scene, settings, method.name(), o),
            None => format!("exr {} {width}x{height}", scene.name),
        };
        if !self.loaded.contains_key(&key) {
            let mut r = match rendered {
                None => {
                    let path = config.reference_exr(&scene.name, width, height).expect("an exr reference");
                    read(&path, scene, width, height)?
                }
                Some((method, settings, o)) => {
                    let matched =
                        matches!(spec, ReferenceSpec::Render { samples: ReferenceSamples::Match, .. });
                    self.render(method, &settings, &o, matched, scene, gpu)?
                }
            };
            let png = format!("references/{}.png", r.record.key);
            image_io::write_png(out_dir.join(&png), &r.image)?;
            r.record.png = Some(png);
            let copy = format!("references/{}.exr", r.record.key);
            link_or_copy(Path::new(&r.record.exr), &out_dir.join(&copy))?;
            r.record.exr_copy = Some(copy);
            self.loaded.insert(key.clone(), r);
        }
        Ok(self.loaded.get(&key))
    }

    /// Every reference loaded so far.
    pub fn records(&self) -> Vec<ReferenceRecord> {
        self.loaded.values().map(|r| r.record.clone()).collect()
    }

    fn render(
        &self,
        method: Method,
        settings: &RenderSettings,
        options: &MethodOptions,
        matched: bool,
        scene: &Scene,
        gpu: &mut GpuSlot,
    ) -> Result<Reference> {
        let (width, height, spp) = (settings.width, settings.height, settings.spp);
        let key = cache_key(scene, settings, method.name(), options);
        let path = self.cache_dir.join(format!("{key}.exr"));
        let mut record = ReferenceRecord {
            key: key.clone(),
            scene: scene.name.clone(),
            width,
            height,
            kind: "render".into(),
            method: Some(method.name().into()),
            spp: Some(spp),
            max_depth: Some(settings.max_depth),
            seed: Some(settings.seed),
            nee: Some(settings.nee),
            roulette: Some(settings.roulette),
            options: Some(options_json(options)),
            spp_match: matched,
            exr: path.display().to_string(),
            cached: true,
            render_seconds: 0.0,
            git_commit: None,
            png: None,
            exr_copy: None,
        };
        // Shards sharing the cache render a missing entry once: the first claims it, the others
        // wait for its lock to go (or go stale) and then read the entry (cache_lock.rs).
        std::fs::create_dir_all(&self.cache_dir)
            .with_context(|| format!("creating the reference cache {}", self.cache_dir.display()))?;
        let lock_path = cache_lock::lock_path(&path);
        let mut waited = false;
        let _lock = loop {
            if let Some(image) = from_cache(&path, width, height, &mut record) {
                log::info!("reference {key}: from the cache {}", path.display());
                return Ok(Reference { image, record });
            }
            let claim = cache_lock::try_claim(&lock_path, cache_lock::STALE_AFTER)
                .with_context(|| format!("claiming the reference cache entry {}", lock_path.display()))?;
            match claim {
                // Finished by another between the look above and the claim: read it.
                cache_lock::Claim::Mine(lock) => match from_cache(&path, width, height, &mut record) {
                    Some(image) => return Ok(Reference { image, record }),
                    None => break lock,
                },
                cache_lock::Claim::Held(holder) => {
                    if !waited {
                        eprintln!(
                            "reference {key}: waiting for {} ({holder}), which is rendering it",
                            lock_path.display()
                        );
                        waited = true;
                    }
                    std::thread::sleep(LOCK_POLL);
                }
            }
        };
        eprintln!("rendering reference {key} ({} at {spp} spp)", method.name());
        let ctx = if method.needs_gpu() { Some(gpu.get()?) } else { None };
        let progress = Progress::new(settings.sample_count(), &format!("reference {}", scene.name));
        // A checkpoint for the Python package's Ctrl-C (`cancel.rs`): a reference can take minutes.
        let out = method::render(method, scene, settings, options, ctx, &|d| {
            crate::cancel::checkpoint();
            progress.set(d)
        })
        .with_context(|| format!("rendering the reference for {} at {width}x{height}", scene.name))?;
        progress.finish();
        let report = RunReport::new(scene, method, settings, ctx.map(|c| &c.summary), &out);
        let image = RgbImage { width, height, data: out.film.mean_rgb() };
        image_io::write_exr(&path, &image, &report.exr_attributes())?;
        record.cached = false;
        record.render_seconds = out.wall_seconds;
        record.git_commit = Some(report.build.git_commit.to_string());
        Ok(Reference { image, record })
    }
}

/// How often a shard waiting for another's reference looks again.
const LOCK_POLL: std::time::Duration = std::time::Duration::from_millis(250);

/// The cached entry at `path` if it is a readable EXR of the right size (its commit into
/// `record`); a damaged or foreign file is said to be so and left to be rendered again.
fn from_cache(path: &Path, width: u32, height: u32, record: &mut ReferenceRecord) -> Option<RgbImage> {
    if !path.exists() {
        return None;
    }
    match image_io::read_exr(path) {
        Ok((image, attrs)) if (image.width, image.height) == (width, height) => {
            record.git_commit = attribute(&attrs, "wavetrace.git_commit");
            Some(image)
        }
        Ok((image, _)) => {
            eprintln!(
                "reference cache file {} is {}x{}, not {width}x{height}; rendering it again",
                path.display(),
                image.width,
                image.height
            );
            None
        }
        Err(e) => {
            eprintln!("reference cache file {} is unreadable ({e}); rendering it again", path.display());
            None
        }
    }
}

fn read(path: &Path, scene: &Scene, width: u32, height: u32) -> Result<Reference> {
    let (image, attrs) = image_io::read_exr(path)?;
    anyhow::ensure!(
        (image.width, image.height) == (width, height),
        "reference {} is {}x{}, the runs are {width}x{height}",
        path.display(),
        image.width,
        image.height
    );
    let key = format!(
        "{}-{width}x{height}-exr-{:016x}",
        file_safe(&scene.name),
        fnv1a(path.display().to_string().as_bytes())
    );
    let record = ReferenceRecord {
        key,
        scene: scene.name.clone(),
        width,
        height,
        kind: "exr".into(),
        method: attribute(&attrs, "wavetrace.method"),
        spp: attribute(&attrs, "wavetrace.spp").and_then(|s| s.parse().ok()),
        max_depth: attribute(&attrs, "wavetrace.max_depth").and_then(|s| s.parse().ok()),
        nee: attribute(&attrs, "wavetrace.nee").map(|s| s == "on"),
        roulette: attribute(&attrs, "wavetrace.roulette").map(|s| s != "off"),
        seed: attribute(&attrs, "wavetrace.seed").and_then(|s| s.parse().ok()),
        options: {
            let knobs: serde_json::Map<String, serde_json::Value> = REFERENCE_KNOBS
                .iter()
                .filter_map(|k| Some((k.to_string(), attribute(&attrs, &format!("wavetrace.{k}"))?.into())))
                .collect();
            (!knobs.is_empty()).then_some(serde_json::Value::Object(knobs))
        },
        spp_match: false,
        exr: path.display().to_string(),
        cached: false,
        render_seconds: 0.0,
        git_commit: attribute(&attrs, "wavetrace.git_commit"),
        png: None,
        exr_copy: None,
    };
    Ok(Reference { image, record })
}

/// The knobs a reference is rendered with (and, read from an EXR, those its attributes name).
const REFERENCE_KNOBS: [&str; 5] = ["ray_offset", "sphere_hit", "fresnel", "light_sampling", "light_select"];

/// A reference's knobs, as the config spells them.
fn options_json(o: &MethodOptions) -> serde_json::Value {
    serde_json::json!({
        "ray_offset": o.numerics.ray_offset,
        "sphere_hit": o.numerics.sphere_hit,
        "fresnel": o.numerics.fresnel,
        "light_sampling": o.lights.sampling,
        "light_select": o.lights.select,
    })
}

fn attribute(attrs: &[(String, String)], name: &str) -> Option<String> {
    attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone())
}

/// `scene-WxH-method-SPPspp-dDEPTH-sSEED-HASH`, the hash over everything that determines the
/// image: the scene's exact text, the settings, the method, the crate version and the knobs
/// (`options`) that are away from their defaults; default knobs add nothing, so a reference
/// cached before the knobs existed keeps its key.
pub fn cache_key(scene: &Scene, s: &RenderSettings, method: &str, options: &MethodOptions) -> String {
    let mut knobs = String::new();
    if options.lights != LightOptions::default() {
        knobs += &format!("\nlights {} {}", options.lights.sampling.name(), options.lights.select.name());
    }
    let n = &options.numerics;
    if *n != NumericOptions::default() {
        knobs += &format!("\nnumerics {} {} {}", n.ray_offset.name(), n.sphere_hit.name(), n.fresnel.name());
    }
    if !options.stress.is_identity() {
        knobs += &format!("\nstress {:?} {:?}", options.stress.scale, options.stress.translate);
    }
    // Only when on, so that references cached before roulette existed keep their keys.
    if s.roulette {
        knobs += "\nroulette pbrt-v4";
    }
    let identity = format!(
        "{}\n{}\n{}\n{}x{} spp {} depth {} seed {} accel {:?} nee {} {method}{knobs}",
        env!("CARGO_PKG_VERSION"),
        crate::scene::export::to_json(scene),
        mesh_digest(scene),
        s.width,
        s.height,
        s.spp,
        s.max_depth,
        s.seed,
        s.accel,
        s.nee
    );
    format!(
        "{}-{}x{}-{method}-{}spp-d{}-s{}-{:016x}",
        file_safe(&scene.name),
        s.width,
        s.height,
        s.spp,
        s.max_depth,
        s.seed,
        fnv1a(identity.as_bytes())
    )
}

/// The meshes' vertices, hashed: a scene file names its OBJ files only by path, so an edited
/// mesh must change the key by itself.
fn mesh_digest(scene: &Scene) -> String {
    let digests: Vec<String> = scene
        .meshes
        .iter()
        .map(|m| {
            let bytes: Vec<u8> =
                m.triangles.iter().flatten().flat_map(|v| v.to_array()).flat_map(f32::to_le_bytes).collect();
            format!("{:016x}", fnv1a(&bytes))
        })
        .collect();
    digests.join(" ")
}

/// 64-bit FNV-1a: stable across builds and platforms, unlike `std`'s hasher.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// `to` becomes `from`'s content: a hard link (no second copy of a large EXR) where both are on
/// one filesystem, else a copy; whatever was at `to` (an earlier attempt's) is replaced.
fn link_or_copy(from: &Path, to: &Path) -> Result<()> {
    if let Some(dir) = to.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    if to.exists() {
        std::fs::remove_file(to).with_context(|| format!("cannot replace {}", to.display()))?;
    }
    if std::fs::hard_link(from, to).is_err() {
        std::fs::copy(from, to)
            .with_context(|| format!("cannot copy the reference {} to {}", from.display(), to.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_published_vectors() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn cache_keys_change_with_everything_that_changes_the_image() {
        let scene = crate::scene::builtin::by_name("three-spheres").unwrap();
        let s = RenderSettings::default();
        let o = MethodOptions::default();
        let base = cache_key(&scene, &s, "cpu-f64", &o);
        assert_eq!(base, cache_key(&scene, &s, "cpu-f64", &o));
        assert_ne!(base, cache_key(&scene, &s, "cpu", &o));
        assert_ne!(base, cache_key(&scene, &RenderSettings { seed: 7, ..s.clone() }, "cpu-f64", &o));
        assert_ne!(base, cache_key(&scene, &RenderSettings { spp: 7, ..s.clone() }, "cpu-f64", &o));
        assert_ne!(base, cache_key(&scene, &RenderSettings { roulette: true, ..s.clone() }, "cpu-f64", &o));
        let mut moved = scene.clone();
        moved.camera.vfov += 1.0;
        assert_ne!(base, cache_key(&moved, &s, "cpu-f64", &o));
        // Every knob away from its default changes the key; each differently.
        let mut keys = vec![base.clone()];
        let mut knob = |edit: &dyn Fn(&mut MethodOptions)| {
            let mut o = MethodOptions::default();
            edit(&mut o);
            let k = cache_key(&scene, &s, "cpu-f64", &o);
            assert!(!keys.contains(&k), "{k}");
            keys.push(k);
        };
        knob(&|o| o.numerics.fresnel = crate::numerics::Fresnel::Exact);
        knob(&|o| o.numerics.sphere_hit = crate::numerics::SphereHit::Book);
        knob(&|o| o.numerics.ray_offset = crate::numerics::RayOffset::Robust);
        knob(&|o| o.numerics.ray_offset = crate::numerics::RayOffset::Tmin(1e-4));
        knob(&|o| o.lights.select = crate::light_options::LightSelect::Uniform);
        knob(&|o| o.stress.scale = 2.0);
    }

    #[test]
    fn default_knobs_keep_the_keys_of_references_cached_before_them() {
        // The key of three-spheres' default reference as this crate version computed it before
        // the knobs existed: identity text without a knob line.
        let scene = crate::scene::builtin::by_name("three-spheres").unwrap();
        let s = RenderSettings::default();
        let RenderSettings { width, height, spp, max_depth, seed, accel, nee, .. } = s.clone();
        let (v, json) = (env!("CARGO_PKG_VERSION"), crate::scene::export::to_json(&scene));
        let digest = mesh_digest(&scene);
        let identity = format!(
            "{v}\n{json}\n{digest}\n{width}x{height} spp {spp} depth {max_depth} seed {seed} accel {accel:?} nee {nee} cpu-f64"
        );
        let key = cache_key(&scene, &s, "cpu-f64", &MethodOptions::default());
        assert!(key.ends_with(&format!("{:016x}", fnv1a(identity.as_bytes()))), "{key}");
    }
}
