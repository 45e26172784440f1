//! Reference images: read from EXRs the config names, or rendered once and cached on disk under a
//! key made of the scene's exact text, the size and how the reference is made, so reruns and
//! other shards sharing the cache directory reuse it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::config::{ExperimentConfig, ReferenceSpec};
use super::gpu_slot::GpuSlot;
use super::plan::file_safe;
use super::report::ReferenceRecord;
use crate::image_io::{self, RgbImage};
use crate::method::{self, MethodOptions};
use crate::progress::Progress;
use crate::report::RunReport;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// A loaded reference and its record.
pub struct Reference {
    pub image: RgbImage,
    pub record: ReferenceRecord,
}

/// The references met so far, by (scene, width, height).
pub struct References {
    cache_dir: PathBuf,
    loaded: BTreeMap<(String, u32, u32), Reference>,
}

impl References {
    pub fn new(cache_dir: PathBuf) -> Self {
        Self { cache_dir, loaded: BTreeMap::new() }
    }

    /// The reference for `scene` at `width`×`height`, loading or rendering it on first use; `None`
    /// when the config has no reference. `out_dir` receives its PNG preview.
    pub fn get(
        &mut self,
        config: &ExperimentConfig,
        scene: &Scene,
        width: u32,
        height: u32,
        gpu: &mut GpuSlot,
        out_dir: &Path,
    ) -> Result<Option<&Reference>> {
        let Some(spec) = &config.reference else { return Ok(None) };
        let key = (scene.name.clone(), width, height);
        if !self.loaded.contains_key(&key) {
            let r = match spec {
                ReferenceSpec::Exr { .. } => {
                    let path = config.reference_exr(&scene.name, width, height).expect("an exr reference");
                    read(&path, scene, width, height)?
                }
                ReferenceSpec::Render { .. } => self.render(config, spec, scene, width, height, gpu)?,
            };
            let mut r = r;
            let png = format!("references/{}.png", r.record.key);
            image_io::write_png(out_dir.join(&png), &r.image)?;
            r.record.png = Some(png);
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
        config: &ExperimentConfig,
        spec: &ReferenceSpec,
        scene: &Scene,
        width: u32,
        height: u32,
        gpu: &mut GpuSlot,
    ) -> Result<Reference> {
        let ReferenceSpec::Render { method, spp, max_depth, seed, nee } = *spec else { unreachable!() };
        let settings = RenderSettings { width, height, spp, max_depth, seed, accel: config.accel, nee };
        let key = cache_key(scene, &settings, method.name());
        let path = self.cache_dir.join(format!("{key}.exr"));
        let mut record = ReferenceRecord {
            key: key.clone(),
            scene: scene.name.clone(),
            width,
            height,
            kind: "render".into(),
            method: Some(method.name().into()),
            spp: Some(spp),
            max_depth: Some(max_depth),
            seed: Some(seed),
            nee: Some(nee),
            exr: path.display().to_string(),
            cached: true,
            render_seconds: 0.0,
            git_commit: None,
            png: None,
        };
        if path.exists() {
            match image_io::read_exr(&path) {
                Ok((image, attrs)) if (image.width, image.height) == (width, height) => {
                    log::info!("reference {key}: from the cache {}", path.display());
                    record.git_commit = attribute(&attrs, "wavetrace.git_commit");
                    return Ok(Reference { image, record });
                }
                // A damaged or foreign cache file is replaced, not trusted.
                _ => log::warn!("reference cache file {} is unreadable; rendering it again", path.display()),
            }
        }
        eprintln!("rendering reference {key} ({} at {spp} spp)", method.name());
        let ctx = if method.needs_gpu() { Some(gpu.get()?) } else { None };
        let progress = Progress::new(settings.sample_count(), &format!("reference {}", scene.name));
        let options = MethodOptions::default();
        let out = method::render(method, scene, &settings, &options, ctx, &|d| progress.set(d))
            .with_context(|| format!("rendering the reference for {} at {width}x{height}", scene.name))?;
        progress.finish();
        let report = RunReport::new(scene, method, &settings, &options, ctx.map(|c| &c.summary), &out);
        let image = RgbImage { width, height, data: out.film.mean_rgb() };
        std::fs::create_dir_all(&self.cache_dir)
            .with_context(|| format!("creating the reference cache {}", self.cache_dir.display()))?;
        image_io::write_exr(&path, &image, &report.exr_attributes())?;
        record.cached = false;
        record.render_seconds = out.wall_seconds;
        record.git_commit = Some(report.build.git_commit.to_string());
        Ok(Reference { image, record })
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
        seed: attribute(&attrs, "wavetrace.seed").and_then(|s| s.parse().ok()),
        exr: path.display().to_string(),
        cached: false,
        render_seconds: 0.0,
        git_commit: attribute(&attrs, "wavetrace.git_commit"),
        png: None,
    };
    Ok(Reference { image, record })
}

fn attribute(attrs: &[(String, String)], name: &str) -> Option<String> {
    attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone())
}

/// `scene-WxH-method-SPPspp-dDEPTH-sSEED-HASH`, the hash over everything that determines the
/// image: the scene's exact text, the settings, the method and the crate version.
pub fn cache_key(scene: &Scene, s: &RenderSettings, method: &str) -> String {
    let identity = format!(
        "{}\n{}\n{}\n{}x{} spp {} depth {} seed {} accel {:?} nee {} {method}",
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
        let base = cache_key(&scene, &s, "cpu-f64");
        assert_eq!(base, cache_key(&scene, &s, "cpu-f64"));
        assert_ne!(base, cache_key(&scene, &s, "cpu"));
        assert_ne!(base, cache_key(&scene, &RenderSettings { seed: 7, ..s.clone() }, "cpu-f64"));
        let mut moved = scene.clone();
        moved.camera.vfov += 1.0;
        assert_ne!(base, cache_key(&moved, &s, "cpu-f64"));
    }
}
