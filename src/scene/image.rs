//! Image textures: a PNG's texels, looked up through a surface's texture coordinates (glTF
//! `baseColorTexture`, a scene file's `{"type": "image", ...}` albedo).
//!
//! Texels are kept as the file's 8-bit sRGB-encoded bytes, one `u32` per texel (r | g << 8 |
//! b << 16), and decoded to linear through one 256-entry table ([`srgb_table`]) built once: every
//! method reads the same table, so a texel's linear value is the same f32 on the CPU and the GPU,
//! at a quarter of the memory of linear f32 RGB. The lookup (`cpu/image_texture.rs`, its twin
//! `shaders/shared/image_texture.wgsl`) is bilinear in linear space, with texel centres at
//! (i + ½) / width, v = 0 the image's first (top) row, as glTF's UVs are defined.

use std::path::PathBuf;

/// Largest width or height an image may have: the common GPU texture limit, which also keeps
/// the lookup's integer arithmetic well inside i32.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// How a texture coordinate outside [0, 1] wraps (glTF `sampler.wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// The image tiles (glTF REPEAT, 10497; its default).
    #[default]
    Repeat,
    /// The edge texels extend outward (CLAMP_TO_EDGE, 33071).
    Clamp,
    /// The image tiles, every other copy mirrored (MIRRORED_REPEAT, 33648).
    Mirror,
}

impl Wrap {
    pub const ALL: [Wrap; 3] = [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror];

    /// The stable name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Wrap::Repeat => "repeat",
            Wrap::Clamp => "clamp",
            Wrap::Mirror => "mirror",
        }
    }

    pub fn from_name(name: &str) -> Option<Wrap> {
        Wrap::ALL.into_iter().find(|w| w.name() == name)
    }

    /// The code the material record holds (`WRAP_*` in image_texture.wgsl).
    pub fn code(self) -> u32 {
        self as u32
    }

    pub fn from_code(code: u32) -> Wrap {
        match code {
            1 => Wrap::Clamp,
            2 => Wrap::Mirror,
            _ => Wrap::Repeat,
        }
    }
}

/// Where an image came from, as errors and `scene info` name it.
#[derive(Clone, Debug, PartialEq)]
pub enum ImageSource {
    /// A PNG file (absolute), as a scene file names it (`"file"`).
    File(PathBuf),
    /// An image of a glTF file (absolute): `image` is its glTF path, e.g. `images[0]`. Scene
    /// files cannot refer to one.
    Gltf { file: PathBuf, image: String },
}

impl std::fmt::Display for ImageSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ImageSource::File(p) => write!(f, "{}", p.display()),
            ImageSource::Gltf { file, image } => write!(f, "{} {image}", file.display()),
        }
    }
}

/// A decoded image: `width` × `height` texels, rows top first.
#[derive(Clone, Debug)]
pub struct Image {
    pub source: ImageSource,
    pub width: u32,
    pub height: u32,
    /// sRGB-encoded bytes, r | g << 8 | b << 16 (alpha dropped: surfaces are opaque).
    pub texels: Vec<u32>,
}

/// Two images are the same texture whatever file they came from.
impl PartialEq for Image {
    fn eq(&self, o: &Self) -> bool {
        (self.width, self.height) == (o.width, o.height) && self.texels == o.texels
    }
}

impl Image {
    /// Decodes PNG bytes (8-bit or 16-bit, grey, RGB, palette, with or without alpha). The error
    /// is the reason alone; the caller names the file and field.
    pub fn from_png(bytes: &[u8], source: ImageSource) -> Result<Image, String> {
        if !bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            let what = if bytes.starts_with(b"\xff\xd8\xff") { "a JPEG" } else { "not a PNG" };
            return Err(format!("{what} (no PNG signature); this build decodes PNG images only"));
        }
        let (width, height, rgb) =
            crate::image_io::decode_png_rgb8(bytes).map_err(|e| format!("the PNG cannot be decoded: {e}"))?;
        if width == 0 || height == 0 {
            return Err("the image is empty".into());
        }
        if width.max(height) > MAX_IMAGE_SIDE {
            return Err(format!(
                "the image is {width}×{height}; images may be at most {MAX_IMAGE_SIDE} a side"
            ));
        }
        let texels =
            rgb.chunks(3).map(|p| u32::from(p[0]) | u32::from(p[1]) << 8 | u32::from(p[2]) << 16).collect();
        Ok(Image { source, width, height, texels })
    }

    /// Reads a PNG file.
    pub fn read_png(path: &std::path::Path) -> Result<Image, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Image::from_png(&bytes, ImageSource::File(path.to_owned()))
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The mean linear colour of the texels.
    pub fn mean(&self) -> glam::Vec3 {
        let table = srgb_table();
        let sum = self.texels.iter().fold(glam::DVec3::ZERO, |acc, &t| {
            acc + glam::DVec3::new(
                f64::from(table[(t & 0xff) as usize]),
                f64::from(table[(t >> 8 & 0xff) as usize]),
                f64::from(table[(t >> 16 & 0xff) as usize]),
            )
        });
        (sum / self.texels.len() as f64).as_vec3()
    }
}

/// The sRGB decoding of each byte value (IEC 61966-2-1), to linear, rounded once to f32.
pub fn srgb_table() -> [f32; 256] {
    std::array::from_fn(|b| srgb_to_linear(b as f64 / 255.0) as f32)
}

pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_table_ends_and_mid_grey() {
        let t = srgb_table();
        assert_eq!((t[0], t[255]), (0.0, 1.0));
        assert!((t[128] - 0.2158605).abs() < 1e-6, "{}", t[128]);
        assert!(t.windows(2).all(|w| w[0] < w[1]), "increasing");
    }

    #[test]
    fn non_png_bytes_are_refused_with_a_reason() {
        let src = || ImageSource::File("x.png".into());
        assert!(Image::from_png(b"\xff\xd8\xff\xe0 JFIF", src()).unwrap_err().contains("a JPEG"));
        assert!(Image::from_png(b"GIF89a", src()).unwrap_err().contains("not a PNG"));
        assert!(Image::from_png(b"\x89PNG\r\n\x1a\n\0\0", src()).unwrap_err().contains("cannot be decoded"));
    }

    #[test]
    fn wrap_names_and_codes_round_trip() {
        for w in Wrap::ALL {
            assert_eq!(Wrap::from_name(w.name()), Some(w));
            assert_eq!(Wrap::from_code(w.code()), w);
        }
    }
}
