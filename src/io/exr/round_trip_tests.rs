//! glassscan's writer against the `exr` crate: random images of many sizes and kinds of
//! samples read back bit for bit, with the header the `exr` crate itself would write; raw and
//! compressed blocks; files that do not depend on the number of threads.

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, FlatSamples,
    ImageAttributes, IntegerBounds, Layer, LayerAttributes, LineOrder, SmallVec, Text,
    WritableImage,
};

use super::zip_block::{Samples, LINES_PER_BLOCK};
use super::*;

/// SplitMix64: the tests' random numbers, the same on every run.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn uniform(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// What a test channel holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// All zero: runs of 128 after the predictor.
    Zeros,
    /// Random bits (NaNs and infinities among them): incompressible, so its blocks are raw.
    Noise,
    /// Only special values: NaNs with payloads, ±inf, ±0, subnormals, extremes.
    Special,
    /// Mostly zero with scattered tiny values, like stray light.
    Sparse,
    /// A smooth ramp.
    Ramp,
    /// A copy of the first channel (the irradiance total where one class carries it all);
    /// noise as the first channel.
    Copy,
}

const KINDS: [Kind; 6] = [
    Kind::Zeros,
    Kind::Noise,
    Kind::Special,
    Kind::Sparse,
    Kind::Ramp,
    Kind::Copy,
];

const SPECIAL_BITS: [u32; 14] = [
    0x7fc0_0000, // quiet NaN
    0x7fc0_0001, // quiet NaN with a payload
    0x7f80_0001, // signalling NaN
    0xffc1_2345, // negative NaN with a payload
    0x7f80_0000, // +inf
    0xff80_0000, // -inf
    0x8000_0000, // -0
    0x0000_0000, // +0
    0x0000_0001, // smallest subnormal
    0x007f_ffff, // largest subnormal
    0x8000_0001, // negative subnormal
    0x0da2_4260, // 1e-30
    0x7f7f_ffff, // f32::MAX
    0x0080_0000, // f32::MIN_POSITIVE
];

fn channel(kind: Kind, width: usize, height: usize, first: &[f32], rng: &mut SplitMix) -> Vec<f32> {
    let len = width * height;
    match kind {
        Kind::Zeros => vec![0.0; len],
        Kind::Copy if first.len() == len => first.to_vec(),
        Kind::Noise | Kind::Copy => (0..len)
            .map(|_| f32::from_bits(rng.next() as u32))
            .collect(),
        Kind::Special => (0..len)
            .map(|_| f32::from_bits(SPECIAL_BITS[rng.below(SPECIAL_BITS.len())]))
            .collect(),
        Kind::Sparse => (0..len)
            .map(|_| {
                if rng.below(30) == 0 {
                    1e-9 * rng.uniform()
                } else {
                    0.0
                }
            })
            .collect(),
        Kind::Ramp => (0..len)
            .map(|i| (i % width) as f32 * 0.25 + (i / width) as f32 * 3.0)
            .collect(),
    }
}

/// The file the `exr` crate writes for these layers and attributes: how glassscan wrote EXRs
/// before it had a writer of its own.
fn exr_crate_file(
    width: usize,
    height: usize,
    layers: &[(&str, &[f32])],
    layer_attributes: LayerAttributes,
    image_custom: Option<(Text, AttributeValue)>,
) -> Vec<u8> {
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = layers
        .iter()
        .map(|&(name, samples)| {
            AnyChannel::new(Text::new_or_panic(name), FlatSamples::F32(samples.to_vec()))
        })
        .collect();
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        (width, height),
        layer_attributes,
        encoding,
        AnyChannels::sort(channels),
    );
    let mut image_attributes = ImageAttributes::new(IntegerBounds::new((0, 0), (width, height)));
    image_attributes.other.extend(image_custom);
    let mut out = std::io::Cursor::new(Vec::new());
    exr::prelude::Image::new(image_attributes, layer)
        .write()
        .to_buffered(&mut out)
        .unwrap();
    out.into_inner()
}

fn read_i32(bytes: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

/// Where the header ends (after its terminating NUL), by walking its attributes.
fn header_end(bytes: &[u8]) -> usize {
    let mut at = 8;
    let nul_after = |at: usize| at + bytes[at..].iter().position(|&b| b == 0).unwrap() + 1;
    while bytes[at] != 0 {
        at = nul_after(nul_after(at)); // name, type
        at += 4 + read_i32(bytes, at) as usize;
    }
    at + 1
}

/// The stored size of each block, checking the offset table and the blocks' y on the way.
fn block_sizes(bytes: &[u8], height: usize) -> Vec<usize> {
    let count = height.div_ceil(LINES_PER_BLOCK);
    let table = header_end(bytes);
    let mut at = table + 8 * count;
    let mut sizes = Vec::new();
    for b in 0..count {
        let offset =
            u64::from_le_bytes(bytes[table + 8 * b..table + 8 * b + 8].try_into().unwrap());
        assert_eq!(offset as usize, at, "block {b}'s offset");
        assert_eq!(
            read_i32(bytes, at) as usize,
            b * LINES_PER_BLOCK,
            "block {b}'s y"
        );
        let size = read_i32(bytes, at + 4) as usize;
        sizes.push(size);
        at += 8 + size;
    }
    assert_eq!(at, bytes.len(), "the last block ends the file");
    sizes
}

fn bits(data: &[f32]) -> Vec<u32> {
    data.iter().map(|v| v.to_bits()).collect()
}

/// Layer names: sorted or not, one longer than 31 bytes, one with a Latin-1 letter.
const NAMES: [&str; 13] = [
    "irradiance",
    "class.glass_face",
    "class.background",
    "a",
    "Z",
    "class.a_name_longer_than_31_bytes_in_all",
    "R",
    "zé",
    "class.glint",
    "class.table",
    "class.other",
    "b.c",
    "class.target",
];

#[test]
fn random_images_read_back_bit_for_bit_with_the_exr_crates_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("random.exr");
    let mut rng = SplitMix(42);
    let (mut raw_blocks, mut compressed_blocks) = (0, 0);
    let sizes = [
        (1, 1),
        (3, 2),
        (5, 15),
        (7, 16),
        (9, 17),
        (31, 33),
        (64, 48),
        (17, 100),
        (200, 35),
    ];
    for (case, &(width, height)) in sizes.iter().enumerate() {
        for channel_count in [1, 13] {
            // Every kind comes first in some case.
            let mut kinds = vec![KINDS[case % KINDS.len()]];
            kinds.extend((1..channel_count).map(|_| KINDS[rng.below(KINDS.len())]));
            let first = channel(kinds[0], width, height, &[], &mut SplitMix(7));
            let data: Vec<Vec<f32>> = kinds
                .iter()
                .map(|&k| channel(k, width, height, &first, &mut rng))
                .collect();
            let names: Vec<&str> = if channel_count == 1 {
                vec![NAMES[case % NAMES.len()]]
            } else {
                NAMES.to_vec()
            };
            let layers: Vec<(&str, &[f32])> = names
                .iter()
                .zip(&data)
                .map(|(&n, d)| (n, d.as_slice()))
                .collect();
            let what = format!("{width} x {height}, {kinds:?}");

            write_exr_layers(&path, width, height, &layers).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let read = read_exr_layers(&path).unwrap();
            let mut expected = layers.clone();
            expected.sort_by_key(|&(name, _)| header::latin1(name).unwrap());
            assert_eq!(read.len(), expected.len(), "{what}");
            for ((name, img), (expected_name, expected_data)) in read.iter().zip(&expected) {
                assert_eq!(name, expected_name, "{what}");
                assert_eq!((img.width, img.height), (width, height), "{what}");
                assert!(bits(&img.data) == bits(expected_data), "{what}: {name}");
            }

            // The header is the exr crate's, but for the long-names flag: the exr crate does
            // not set it for a channel name longer than 31 bytes, OpenEXR does.
            let mut reference =
                exr_crate_file(width, height, &layers, LayerAttributes::default(), None);
            let end = header_end(&bytes);
            assert_eq!(end, header_end(&reference), "{what}");
            let long_names = names.iter().any(|n| n.len() > 31);
            let flags = u32::from_le_bytes(bytes[4..8].try_into().unwrap());
            assert_eq!(flags & header::LONG_NAMES != 0, long_names, "{what}");
            reference[5] |= bytes[5] & (header::LONG_NAMES >> 8) as u8;
            assert_eq!(bytes[..end], reference[..end], "{what}: header");

            let raw_size = |b: usize| {
                let rows = LINES_PER_BLOCK.min(height - b * LINES_PER_BLOCK);
                rows * width * channel_count * 4
            };
            for (b, size) in block_sizes(&bytes, height).into_iter().enumerate() {
                assert!(size <= raw_size(b), "{what}: block {b}");
                if size == raw_size(b) {
                    raw_blocks += 1;
                } else {
                    compressed_blocks += 1;
                }
            }
        }
    }
    assert!(raw_blocks > 0 && compressed_blocks > 0);
}

#[test]
fn irradiance_header_is_the_exr_crates() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pose.exr");
    let mut rng = SplitMix(3);
    let mut img = crate::sensor::image::Image::new(40, 21);
    img.data
        .iter_mut()
        .for_each(|v| *v = f64::from(rng.uniform()));
    let irradiance = Irradiance {
        by_class: PathClass::ALL.iter().map(|_| img.clone()).collect(),
        total: img,
    };
    let notes = IrradianceNotes {
        wavelength_m: 658e-9,
        exposure_s: 5e-4,
        sensor_to_base: crate::geometry::pose::pose_from_mm_deg(
            [10.0, 20.0, 300.0],
            [180.0, 0.0, 45.0],
        ),
    };
    write_irradiance_exr(&path, &irradiance, &notes).unwrap();
    let bytes = std::fs::read(&path).unwrap();

    // What glassscan set through the exr crate before it wrote its own files.
    let mut layer_attributes = LayerAttributes {
        exposure: Some(notes.exposure_s as f32),
        comments: Some(Text::from(
            "glassscan irradiance at the pixels (W/m^2): 'irradiance' is the total, \
             'class.<path class>' its part by light path",
        )),
        software_name: Some(Text::from(
            format!("glassscan {}", env!("CARGO_PKG_VERSION")).as_str(),
        )),
        ..LayerAttributes::default()
    };
    layer_attributes.other.insert(
        Text::from("sensorToBaseMm"),
        AttributeValue::Matrix4x4(pose_to_matrix_mm(&notes.sensor_to_base).map(|v| v as f32)),
    );
    let wavelength = (
        Text::from("wavelengthNm"),
        AttributeValue::F64(notes.wavelength_m * 1e9),
    );
    let total: Vec<f32> = irradiance.total.data.iter().map(|&v| v as f32).collect();
    let names: Vec<String> = PathClass::ALL
        .iter()
        .map(|c| format!("class.{}", c.name()))
        .collect();
    let mut layers: Vec<(&str, &[f32])> = vec![("irradiance", &total)];
    layers.extend(names.iter().map(|n| (n.as_str(), total.as_slice())));
    let reference = exr_crate_file(40, 21, &layers, layer_attributes, Some(wavelength));

    let end = header_end(&bytes);
    assert_eq!(bytes[..end], reference[..end]);
    for (_, layer) in read_exr_layers(&path).unwrap() {
        assert!(bits(&layer.data) == bits(&total));
    }
}

#[test]
fn file_does_not_depend_on_thread_count() {
    let (width, height) = (640, 200);
    let mut rng = SplitMix(11);
    let first = channel(Kind::Sparse, width, height, &[], &mut rng);
    let data: Vec<Vec<f32>> = KINDS
        .iter()
        .map(|&k| channel(k, width, height, &first, &mut rng))
        .collect();
    let channels: Vec<(Vec<u8>, Samples)> = data
        .iter()
        .enumerate()
        .map(|(i, d)| (vec![b'a' + i as u8], Samples::F32(d)))
        .collect();
    let encode_with = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| file::encode(width, height, &channels, Vec::new()))
    };
    let one = encode_with(1);
    for threads in [2, 3, 8] {
        assert!(encode_with(threads) == one, "{threads} threads");
    }
}
