//! The start of a single-part scanline OpenEXR file: magic number, version field and header
//! (OpenEXR File Layout, openexr.com/en/latest/OpenEXRFileLayout.html, "Magic Number",
//! "Version Field", "Header", and "Predefined Attribute Types" for each value's bytes).
//!
//! An attribute is its name and its type's name, each Latin-1 and NUL-terminated, the value's
//! size in bytes (i32) and the value; the header is its attributes and one NUL byte. Every
//! number is little-endian. The attributes are written in the order they are given: glassscan's
//! is the order the `exr` crate wrote them in before glassscan had a writer of its own, so the
//! header bytes did not change.

/// The four bytes every OpenEXR file starts with (20000630 as a little-endian i32).
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// File format version 2, in the low byte of the version field.
const VERSION: u32 = 2;

/// Version-field flag: some attribute, type or channel name is longer than 31 bytes (as
/// OpenEXR's `usesLongNames` in `ImfHeader.cpp` decides it; the `exr` crate leaves channel
/// names out, and so did glassscan's files with such layer names before it wrote them itself:
/// glassscan's own names are shorter).
pub(super) const LONG_NAMES: u32 = 0x400;

/// The longest name a file without [`LONG_NAMES`] may hold, in bytes.
const SHORT_NAME_MAX: usize = 31;

/// The longest name any file may hold, in bytes.
pub(super) const NAME_MAX: usize = 255;

/// `compression` value of ZIP_COMPRESSION: zlib over blocks of 16 scanlines.
pub(super) const ZIP_COMPRESSION: u8 = 3;

/// `lineOrder` value of INCREASING_Y: blocks stored top to bottom.
const INCREASING_Y: u8 = 0;

/// `chlist` pixel type of 32-bit IEEE 754 floats.
const PIXEL_TYPE_FLOAT: i32 = 2;

/// An attribute's value, as one of the predefined attribute types.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Value {
    /// `int`.
    Int(i32),
    /// `float`.
    Float(f32),
    /// `double`.
    Double(f64),
    /// `string`: Latin-1 bytes, no terminator (the size says how many).
    String(Vec<u8>),
    /// `box2i`: x min, y min, x max, y max (inclusive).
    Box2i([i32; 4]),
    /// `v2f`.
    V2f([f32; 2]),
    /// `m44f`: row-major.
    M44f([f32; 16]),
    /// `compression`.
    Compression(u8),
    /// `lineOrder`.
    LineOrder(u8),
    /// `chlist` of f32 channels, not subsampled, in the order given (the caller sorts them):
    /// each one's name and `pLinear` flag.
    FloatChannels(Vec<(Vec<u8>, bool)>),
}

impl Value {
    /// The attribute type's name as the file spells it.
    fn type_name(&self) -> &'static str {
        match self {
            Value::Int(_) => "int",
            Value::Float(_) => "float",
            Value::Double(_) => "double",
            Value::String(_) => "string",
            Value::Box2i(_) => "box2i",
            Value::V2f(_) => "v2f",
            Value::M44f(_) => "m44f",
            Value::Compression(_) => "compression",
            Value::LineOrder(_) => "lineOrder",
            Value::FloatChannels(_) => "chlist",
        }
    }

    /// Appends the value's bytes to `out`.
    fn encode(&self, out: &mut Vec<u8>) {
        match self {
            Value::Int(v) => out.extend_from_slice(&v.to_le_bytes()),
            Value::Float(v) => out.extend_from_slice(&v.to_le_bytes()),
            Value::Double(v) => out.extend_from_slice(&v.to_le_bytes()),
            Value::String(bytes) => out.extend_from_slice(bytes),
            Value::Box2i(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Value::V2f(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Value::M44f(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Value::Compression(v) | Value::LineOrder(v) => out.push(*v),
            Value::FloatChannels(names) => {
                // Per channel: name and NUL, pixel type (i32), pLinear (u8), three reserved
                // zero bytes, x and y sampling (i32); then one NUL ends the list.
                for (name, linear) in names {
                    out.extend_from_slice(name);
                    out.push(0);
                    out.extend_from_slice(&PIXEL_TYPE_FLOAT.to_le_bytes());
                    out.extend_from_slice(&[u8::from(*linear), 0, 0, 0]);
                    out.extend_from_slice(&1i32.to_le_bytes());
                    out.extend_from_slice(&1i32.to_le_bytes());
                }
                out.push(0);
            }
        }
    }
}

/// A Latin-1 name or text as the file's bytes (one byte per character), or `None` if a
/// character is beyond U+00FF.
pub(super) fn latin1(text: &str) -> Option<Vec<u8>> {
    text.chars().map(|c| u8::try_from(c).ok()).collect()
}

/// The header of a single-part scanline image of `width` × `height` f32 pixels whose
/// `channels` (Latin-1 names, sorted) are ZIP-compressed in `chunk_count` blocks: the required
/// attributes, `chunkCount` and `type` (both optional in a single-part file; kept so that the
/// header reads as it did when the `exr` crate wrote it).
pub(super) fn standard_attributes(
    width: i32,
    height: i32,
    channels: Vec<Vec<u8>>,
    chunk_count: i32,
) -> Vec<(&'static str, Value)> {
    let window = Value::Box2i([0, 0, width - 1, height - 1]);
    let channels = channels
        .into_iter()
        .map(|name| {
            let linear = perceptually_linear(&name);
            (name, linear)
        })
        .collect();
    vec![
        ("chunkCount", Value::Int(chunk_count)),
        ("channels", Value::FloatChannels(channels)),
        ("compression", Value::Compression(ZIP_COMPRESSION)),
        ("lineOrder", Value::LineOrder(INCREASING_Y)),
        ("displayWindow", window.clone()),
        ("pixelAspectRatio", Value::Float(1.0)),
        ("screenWindowCenter", Value::V2f([0.0, 0.0])),
        ("screenWindowWidth", Value::Float(1.0)),
        ("dataWindow", window),
        ("type", Value::String(b"scanlineimage".to_vec())),
    ]
}

/// A channel's `pLinear` flag: a hint for lossy compressors (B44, DWA), ignored by ZIP. Set
/// as the `exr` crate sets it: for every name but R, G, B, L, Y, X and Z (any case), which are
/// perceived logarithmically.
fn perceptually_linear(name: &[u8]) -> bool {
    !matches!(name, [c] if b"RGBLYXZ".contains(&c.to_ascii_uppercase()))
}

/// Magic number, version field and header of `attributes`, in order. Names must be at most
/// [`NAME_MAX`] bytes (the caller checks the channel names; attribute names are glassscan's).
pub(super) fn encode(attributes: &[(&str, Value)]) -> Vec<u8> {
    let mut names = attributes.iter().flat_map(|(name, value)| {
        let channels = match value {
            Value::FloatChannels(channels) => channels.as_slice(),
            _ => &[],
        };
        [name.len(), value.type_name().len()]
            .into_iter()
            .chain(channels.iter().map(|(name, _)| name.len()))
    });
    let long_names = names.any(|len| len > SHORT_NAME_MAX);
    let version = VERSION | if long_names { LONG_NAMES } else { 0 };

    let mut out = Vec::with_capacity(1024);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&version.to_le_bytes());
    let mut value_bytes = Vec::new();
    for (name, value) in attributes {
        debug_assert!(name.is_ascii() && !name.is_empty() && name.len() <= NAME_MAX);
        value_bytes.clear();
        value.encode(&mut value_bytes);
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.extend_from_slice(value.type_name().as_bytes());
        out.push(0);
        let size = i32::try_from(value_bytes.len()).expect("attribute values are small");
        out.extend_from_slice(&size.to_le_bytes());
        out.extend_from_slice(&value_bytes);
    }
    out.push(0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin1_is_one_byte_per_character() {
        assert_eq!(latin1("aé"), Some(vec![b'a', 0xe9]));
        assert_eq!(latin1("λ"), None);
    }

    #[test]
    fn attributes_are_name_type_size_value() {
        let bytes = encode(&[("expTime", Value::Float(0.5))]);
        let mut expected = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
        expected.extend_from_slice(b"expTime\0float\0");
        expected.extend_from_slice(&4i32.to_le_bytes());
        expected.extend_from_slice(&0.5f32.to_le_bytes());
        expected.push(0);
        assert_eq!(bytes, expected);
    }

    #[test]
    fn a_channel_name_longer_than_31_bytes_sets_the_long_names_flag() {
        let channels = |len: usize| Value::FloatChannels(vec![(vec![b'c'; len], true)]);
        let flags = |len| encode(&[("channels", channels(len))])[4..8].to_vec();
        assert_eq!(flags(31), [2, 0, 0, 0]);
        assert_eq!(flags(32), [2, 4, 0, 0]);
    }

    #[test]
    fn only_colour_and_luminance_letters_are_not_perceptually_linear() {
        for name in ["R", "g", "B", "L", "y", "X", "Z"] {
            assert!(!perceptually_linear(name.as_bytes()), "{name}");
        }
        for name in ["A", "irradiance", "RG", "class.glint"] {
            assert!(perceptually_linear(name.as_bytes()), "{name}");
        }
    }
}
