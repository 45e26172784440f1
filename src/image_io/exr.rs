//! OpenEXR files: linear `f32` RGB plus text header attributes.
use std::{collections::HashSet, fs::File, path::Path};

use ::exr::{
    image::{
        read::{image::ReadLayers, layers::ReadChannels, read},
        write::WritableImage,
        AnyChannel, Encoding, FlatSamples, Image, Layer, SpecificChannels,
    },
    math::Vec2,
    meta::{
        attribute::{AttributeValue, Text},
        header::{standard_names, LayerAttributes},
    },
};

use super::{atomic_file::write_atomically, ImageIoError, RgbImage};

/// ZIP (16 scanlines per block) is lossless and the OpenEXR / OpenImageIO default, so every
/// reader handles it; increasing line order keeps the file top row first.
const ENCODING: Encoding = Encoding::SMALL_LOSSLESS;

/// The standard OpenEXR attributes of type text, which the `exr` crate keeps in typed fields
/// rather than among the custom ones; reading and writing both go through this table.
type TextField = for<'a> fn(&'a mut LayerAttributes) -> &'a mut Option<Text>;
const STANDARD_TEXT: [(&str, TextField); 9] = [
    ("capDate", |a| &mut a.capture_date),
    ("comments", |a| &mut a.comments),
    ("lookModTransform", |a| &mut a.look_modification_transform_name),
    ("name", |a| &mut a.layer_name),
    ("owner", |a| &mut a.owner),
    ("renderingTransform", |a| &mut a.rendering_transform_name),
    ("software", |a| &mut a.software_name),
    ("view", |a| &mut a.view_name),
    ("wrapmodes", |a| &mut a.wrap_mode_name),
];

/// Writes `image` as a scanline, ZIP-compressed EXR with `f32` channels R, G, B, atomically.
///
/// Each `(name, value)` becomes a text header attribute (UTF-8). `software` defaults to
/// `wavetrace VERSION`; it and the other standard text attributes (`comments`, `owner`,
/// `capDate`, ...) may be set here too. Names must be unique, non-empty, at most 255 bytes and
/// not a standard attribute of another type (`channels`, `dataWindow`, ...).
pub fn write_exr(
    path: impl AsRef<Path>,
    image: &RgbImage,
    attributes: &[(String, String)],
) -> Result<(), ImageIoError> {
    let path = path.as_ref();
    image.check_writable(path)?;
    let layer_attributes = layer_attributes(path, attributes)?;

    let width = image.width as usize;
    let pixels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let i = 3 * (pos.y() * width + pos.x());
        (image.data[i], image.data[i + 1], image.data[i + 2])
    });
    let size = (width, image.height as usize);
    let exr_image = Image::from_layer(Layer::new(size, layer_attributes, ENCODING, pixels));

    write_atomically(path, |file| {
        exr_image.write().to_buffered(file).map_err(|error| ImageIoError::Exr {
            path: path.to_owned(),
            action: "cannot write OpenEXR",
            error,
        })
    })
}

/// Reads the first layer of an EXR: channels R, G, B (any sample type, converted to `f32`;
/// other channels such as A are ignored), or a lone Y channel copied to all three.
///
/// Returns the pixels of the data window and every text header attribute, sorted by name.
/// Text is decoded as UTF-8, falling back to Latin-1 for files that are not UTF-8.
pub fn read_exr(path: impl AsRef<Path>) -> Result<(RgbImage, Vec<(String, String)>), ImageIoError> {
    let path = path.as_ref();
    let file = File::open(path).map_err(|e| ImageIoError::io(path, "cannot open", e))?;
    let mut exr_image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_unbuffered(file)
        .map_err(|error| ImageIoError::Exr {
            path: path.to_owned(),
            action: "cannot read as OpenEXR",
            error,
        })?;

    let layer = &mut exr_image.layer_data;
    let image = rgb_from_channels(path, layer.size, &layer.channel_data.list)?;

    let mut attributes: Vec<(String, String)> = STANDARD_TEXT
        .iter()
        .filter_map(|(name, field)| {
            let text = field(&mut layer.attributes).as_ref()?;
            Some((name.to_string(), decode(text)))
        })
        .collect();
    let custom = layer.attributes.other.iter().chain(&exr_image.attributes.other);
    attributes.extend(custom.filter_map(|(name, value)| match value {
        AttributeValue::Text(text) => Some((decode(name), decode(text))),
        _ => None,
    }));
    attributes.sort();
    Ok((image, attributes))
}

fn layer_attributes(path: &Path, attributes: &[(String, String)]) -> Result<LayerAttributes, ImageIoError> {
    let mut layer = LayerAttributes {
        software_name: Some(encode(concat!("wavetrace ", env!("CARGO_PKG_VERSION")))),
        ..LayerAttributes::default()
    };
    let mut seen = HashSet::new();
    for (name, value) in attributes {
        let invalid =
            |why: &str| ImageIoError::unsupported(path, format!("header attribute `{name}`: {why}"));
        // Names are NUL-terminated in the file, so NUL cannot round-trip; the 255-byte limit
        // is OpenEXR's (names over 31 bytes set the long-names flag, which the exr crate does).
        if name.is_empty() || name.len() > 255 {
            return Err(invalid("name must be 1 to 255 bytes long"));
        }
        if name.contains('\0') || value.contains('\0') {
            return Err(invalid("name and value must not contain NUL"));
        }
        if !seen.insert(name.as_str()) {
            return Err(invalid("given twice"));
        }
        if let Some((_, field)) = STANDARD_TEXT.iter().find(|(n, _)| n == name) {
            *field(&mut layer) = Some(encode(value));
        } else if standard_names::ALL.contains(&name.as_bytes()) {
            return Err(invalid("reserved: a standard OpenEXR attribute that is not text"));
        } else {
            layer.other.insert(encode(name), AttributeValue::Text(encode(value)));
        }
    }
    Ok(layer)
}

/// Interleaves R, G, B (or Y, Y, Y) into an [`RgbImage`].
fn rgb_from_channels(
    path: &Path,
    size: Vec2<usize>,
    channels: &[AnyChannel<FlatSamples>],
) -> Result<RgbImage, ImageIoError> {
    let find = |name: &str| channels.iter().find(|c| c.name == *name);
    let selected = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => [r, g, b],
        // With RY/BY present, Y is the luminance of a luminance-chroma image: replicating it
        // would silently drop the colour.
        (None, None, None, Some(y)) if find("RY").is_none() && find("BY").is_none() => [y, y, y],
        _ => {
            let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
            return Err(ImageIoError::unsupported(
                path,
                format!(
                    "needs channels R, G, B or a single luminance channel Y; found [{}]",
                    names.join(", ")
                ),
            ));
        }
    };

    let (width, height) = (size.x(), size.y());
    for channel in selected {
        if channel.sampling != Vec2(1, 1) || channel.sample_data.len() != width * height {
            return Err(ImageIoError::unsupported(
                path,
                format!("channel {} is subsampled, which is not supported", channel.name),
            ));
        }
    }
    let too_large = || ImageIoError::unsupported(path, "image dimensions exceed u32");
    let width = u32::try_from(width).map_err(|_| too_large())?;
    let height = u32::try_from(height).map_err(|_| too_large())?;

    let [r, g, b] = selected.map(|c| c.sample_data.values_as_f32());
    let data = r.zip(g).zip(b).flat_map(|((r, g), b)| [r, g, b]).collect();
    Ok(RgbImage::from_data(width, height, data).expect("channel lengths checked above"))
}

/// EXR text is bytes; store UTF-8, which OpenEXR and OpenImageIO assume.
fn encode(text: &str) -> Text {
    Text::from_slice_unchecked(text.as_bytes())
}

fn decode(text: &Text) -> String {
    let bytes = text.as_slice();
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_owned(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}
