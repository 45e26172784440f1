//! Round trips, sRGB encoding and error messages of `wavetrace::image_io`.
use std::{
    fs,
    path::{Path, PathBuf},
};

use exr::prelude::{
    f16, AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SpecificChannels,
    Vec2, WritableImage,
};
use wavetrace::image_io::{linear_to_srgb8, read_exr, write_exr, write_png, ImageIoError, RgbImage};

/// A fresh, empty directory per test, under cargo's scratch directory for integration tests.
fn scratch_dir(test: &str) -> PathBuf {
    let dir = crate::common::tmp().join("image_io").join(test);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    names
}

fn attrs(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs.iter().map(|&(k, v)| (k.to_owned(), v.to_owned())).collect()
}

/// Odd, non-square and taller than one 16-line ZIP block, with the awkward floats first.
fn test_image() -> RgbImage {
    let special = [
        1e-8,
        65504.0,
        1e6,
        0.0,
        -0.0,
        1e-40, // subnormal
        f32::MIN_POSITIVE,
        f32::MAX,
        -f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        f32::from_bits(0x7fc0_1234), // NaN with a payload
        0.1,
        -3.5,
    ];
    let (width, height) = (37, 19);
    let data = (0..3 * width * height)
        .map(|i| special.get(i as usize).copied().unwrap_or((i as f32 * 0.37).sin() * 100.0))
        .collect();
    RgbImage::from_data(width, height, data).unwrap()
}

fn assert_bit_exact(a: &RgbImage, b: &RgbImage) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    for (i, (x, y)) in a.data.iter().zip(&b.data).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "value {i}: {x:e} != {y:e}");
    }
}

fn assert_names_file(err: &ImageIoError, path: &Path) {
    let message = err.to_string();
    assert!(message.contains(&path.display().to_string()), "{message:?} does not name {path:?}");
    assert_eq!(err.path(), path);
}

#[test]
fn rgb_image_basics() {
    let mut image = RgbImage::new(3, 2);
    assert_eq!(image.data.len(), 18);
    image.set(2, 1, [1.0, 2.0, 3.0]);
    assert_eq!(image.get(2, 1), [1.0, 2.0, 3.0]);
    assert_eq!(&image.data[15..], [1.0, 2.0, 3.0]); // row-major, last pixel
    assert_eq!(image.mean(), [1.0 / 6.0, 2.0 / 6.0, 3.0 / 6.0]);
    assert!(RgbImage::from_data(2, 2, vec![0.0; 11]).is_none());
    assert!(RgbImage::new(0, 0).mean()[0].is_nan());
}

#[test]
#[should_panic(expected = "outside 3x2 image")]
fn rgb_image_get_outside_panics() {
    // x = 3 would otherwise alias pixel (0, 1).
    RgbImage::new(3, 2).get(3, 0);
}

#[test]
fn exr_round_trip_is_bit_exact_with_attributes() {
    let dir = scratch_dir("exr_round_trip");
    let path = dir.join("render.exr");
    let image = test_image();
    let given = attrs(&[
        ("wavetrace.method", "megakernel"),
        ("wavetrace.spp", "64"),
        ("wavetrace.seed", "7"),
        ("wavetrace.scene", "scenes/cornell ✓ é.json"),
        ("wavetrace.render_time_s", "1.25"),
        ("wavetrace.a_name_longer_than_thirty_one_bytes", ""),
    ]);
    write_exr(&path, &image, &given).unwrap();
    assert_eq!(file_names(&dir), ["render.exr"]);

    let (back, attributes) = read_exr(&path).unwrap();
    assert_bit_exact(&image, &back);
    let software = format!("wavetrace {}", env!("CARGO_PKG_VERSION"));
    let mut expected = given.clone();
    expected.push(("software".into(), software));
    expected.sort();
    assert_eq!(attributes, expected);
}

#[test]
fn exr_standard_text_attributes_can_be_set() {
    let dir = scratch_dir("exr_standard_text");
    let path = dir.join("a.exr");
    let given = attrs(&[("software", "other tool 2.0"), ("comments", "hello"), ("x", "y")]);
    write_exr(&path, &RgbImage::new(2, 2), &given).unwrap();
    let (_, mut attributes) = read_exr(&path).unwrap();
    attributes.sort();
    let mut expected = given;
    expected.sort();
    assert_eq!(attributes, expected);
}

#[test]
fn exr_overwrite_is_atomic_and_leaves_no_temp_files() {
    let dir = scratch_dir("exr_overwrite");
    let path = dir.join("a.exr");
    write_exr(&path, &RgbImage::new(4, 4), &[]).unwrap();
    let image = test_image();
    write_exr(&path, &image, &[]).unwrap();
    assert_bit_exact(&read_exr(&path).unwrap().0, &image);

    // A failed write leaves the previous file intact.
    let bad = attrs(&[("k", "1"), ("k", "2")]);
    assert!(write_exr(&path, &RgbImage::new(1, 1), &bad).is_err());
    assert_bit_exact(&read_exr(&path).unwrap().0, &image);
    assert_eq!(file_names(&dir), ["a.exr"]);
}

#[test]
fn exr_write_rejects_bad_attributes_naming_the_file() {
    let dir = scratch_dir("exr_bad_attributes");
    let path = dir.join("a.exr");
    let image = RgbImage::new(1, 1);
    for (bad, why) in [
        (attrs(&[("k", "1"), ("k", "2")]), "given twice"),
        (attrs(&[("", "1")]), "1 to 255 bytes"),
        (attrs(&[(&"n".repeat(256), "1")]), "1 to 255 bytes"),
        (attrs(&[("k\0", "1")]), "NUL"),
        (attrs(&[("dataWindow", "1")]), "not text"),
    ] {
        let err = write_exr(&path, &image, &bad).unwrap_err();
        assert_names_file(&err, &path);
        assert!(err.to_string().contains(why), "{err}");
    }
    assert!(file_names(&dir).is_empty());
}

#[test]
fn writers_reject_empty_and_inconsistent_images() {
    let dir = scratch_dir("bad_images");
    let empty = RgbImage::new(0, 5);
    let inconsistent = RgbImage { width: 2, height: 2, data: vec![0.0; 3] };
    for image in [&empty, &inconsistent] {
        let path = dir.join("a.exr");
        assert_names_file(&write_exr(&path, image, &[]).unwrap_err(), &path);
        let path = dir.join("a.png");
        assert_names_file(&write_png(&path, image).unwrap_err(), &path);
    }
    assert!(file_names(&dir).is_empty());
}

#[test]
fn write_into_missing_directory_names_the_file() {
    let path = scratch_dir("missing_dir").join("no/such/dir/a.exr");
    let err = write_exr(&path, &RgbImage::new(1, 1), &[]).unwrap_err();
    assert_names_file(&err, &path);
    let err = write_png(path.with_extension("png"), &RgbImage::new(1, 1)).unwrap_err();
    assert_names_file(&err, &path.with_extension("png"));
}

#[test]
fn exr_reads_f16_rgba_ignoring_alpha() {
    let path = scratch_dir("exr_f16").join("rgba.exr");
    // Each pixel encodes its position, which also checks that row 0 is the top row.
    let pixel = |x: usize, y: usize| {
        let v = |c: usize| f16::from_f32((100 * y + 10 * x + c) as f32 * 0.25);
        (v(0), v(1), v(2), f16::from_f32(0.5))
    };
    let channels = SpecificChannels::rgba(|p: Vec2<usize>| pixel(p.x(), p.y()));
    Image::from_channels((5, 3), channels).write().to_file(&path).unwrap();

    let (image, _) = read_exr(&path).unwrap();
    assert_eq!((image.width, image.height), (5, 3));
    for y in 0..3 {
        for x in 0..5 {
            let (r, g, b, _) = pixel(x, y);
            assert_eq!(image.get(x as u32, y as u32), [r, g, b].map(f16::to_f32));
        }
    }
}

fn write_channels(path: &Path, size: (usize, usize), channels: &[(&str, Vec<f32>)]) {
    let list = channels
        .iter()
        .map(|(name, values)| AnyChannel::new(*name, FlatSamples::F32(values.clone())))
        .collect();
    let layer = Layer::new(size, LayerAttributes::default(), Encoding::UNCOMPRESSED, AnyChannels::sort(list));
    Image::from_layer(layer).write().to_file(path).unwrap();
}

#[test]
fn exr_reads_single_y_channel_as_grey() {
    let path = scratch_dir("exr_y").join("y.exr");
    write_channels(&path, (2, 2), &[("Y", vec![0.0, 1.0, 2.0, 3.0])]);
    let (image, _) = read_exr(&path).unwrap();
    assert_eq!(image.get(1, 1), [3.0; 3]);
    assert_eq!(image.get(1, 0), [1.0; 3]);
}

#[test]
fn exr_without_rgb_is_an_error_naming_file_and_channels() {
    let dir = scratch_dir("exr_no_rgb");
    let path = dir.join("depth.exr");
    write_channels(&path, (2, 1), &[("Z", vec![1.0, 2.0])]);
    let err = read_exr(&path).unwrap_err();
    assert_names_file(&err, &path);
    assert!(err.to_string().contains("found [Z]"), "{err}");

    // Luminance-chroma: replicating Y would drop the colour.
    let path = dir.join("chroma.exr");
    let ones = vec![1.0; 2];
    write_channels(&path, (2, 1), &[("Y", ones.clone()), ("RY", ones.clone()), ("BY", ones)]);
    assert_names_file(&read_exr(&path).unwrap_err(), &path);

    let path = dir.join("rg.exr");
    write_channels(&path, (1, 1), &[("R", vec![1.0]), ("G", vec![1.0])]);
    assert_names_file(&read_exr(&path).unwrap_err(), &path);
}

#[test]
fn exr_read_errors_name_the_file() {
    let dir = scratch_dir("exr_read_errors");

    let missing = dir.join("missing.exr");
    let err = read_exr(&missing).unwrap_err();
    assert_names_file(&err, &missing);
    assert!(matches!(&err, ImageIoError::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound));

    let text = dir.join("text.exr");
    fs::write(&text, "not an image\n").unwrap();
    assert_names_file(&read_exr(&text).unwrap_err(), &text);

    let truncated = dir.join("truncated.exr");
    write_exr(&truncated, &test_image(), &[]).unwrap();
    let bytes = fs::read(&truncated).unwrap();
    fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    assert_names_file(&read_exr(&truncated).unwrap_err(), &truncated);
}

#[test]
fn errors_work_with_anyhow() {
    fn load(path: &Path) -> anyhow::Result<RgbImage> {
        Ok(read_exr(path)?.0)
    }
    let path = scratch_dir("anyhow").join("missing.exr");
    let err = load(&path).unwrap_err();
    assert!(err.to_string().contains("missing.exr"));
    assert!(err.downcast_ref::<ImageIoError>().is_some());
}

#[test]
fn srgb_curve_known_points() {
    assert_eq!(linear_to_srgb8(0.0), 0);
    assert_eq!(linear_to_srgb8(1.0), 255);
    assert_eq!(linear_to_srgb8(0.5), 188); // gamma 2.2 would give 186
    assert_eq!(linear_to_srgb8(0.003_130_8), 10); // end of the linear segment: 10.3
    assert_eq!(linear_to_srgb8(0.001), 3); // linear segment: 3.29; gamma 2.2 would give 11
    assert_eq!(linear_to_srgb8(0.18), 118);
    for v in [1.0001, 2.0, 1e6, f32::MAX, f32::INFINITY] {
        assert_eq!(linear_to_srgb8(v), 255, "{v}");
    }
    for v in [-0.0, -1e-8, -1.0, f32::NEG_INFINITY, f32::NAN, -f32::NAN] {
        assert_eq!(linear_to_srgb8(v), 0, "{v}");
    }
}

#[test]
fn srgb_curve_inverts_the_decoding_curve() {
    // Every code decodes to a linear value that encodes back to the same code.
    for code in 0..=255u8 {
        let s = f64::from(code) / 255.0;
        let linear = if s <= 0.04045 { s / 12.92 } else { ((s + 0.055) / 1.055).powf(2.4) };
        assert_eq!(linear_to_srgb8(linear as f32), code);
    }
}

#[test]
fn png_pixels_follow_the_srgb_curve() {
    let dir = scratch_dir("png");
    let path = dir.join("preview.png");
    let values = [0.0, 1.0, 0.5, 0.003_130_8, 2.0, -1.0, f32::NAN, f32::INFINITY, 0.18];
    let expected = [0u8, 255, 188, 10, 255, 0, 0, 255, 118];
    // Three pixels in the top row, and a marker in the bottom row to pin the orientation.
    let mut image = RgbImage::from_data(3, 2, [values.to_vec(), vec![0.0; 9]].concat()).unwrap();
    image.set(2, 1, [0.0, 0.0, 1.0]);
    write_png(&path, &image).unwrap();
    assert_eq!(file_names(&dir), ["preview.png"]);

    // The file as the png crate's decoder sees it, before any conversion: 8-bit RGB.
    let header =
        png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap())).read_info().unwrap();
    assert_eq!(header.output_color_type(), (png::ColorType::Rgb, png::BitDepth::Eight));
    let (width, height, rgb) = wavetrace::image_io::read_png_rgb8(&path).unwrap();
    assert_eq!((width, height), (3, 2));
    assert_eq!(&rgb[..9], expected);
    assert_eq!(&rgb[3 * (3 + 2)..][..3], [0, 0, 255]);
    assert_eq!(&rgb[3 * 3..][..3], [0, 0, 0]);
}
