//! zlib streams (RFC 1950) of the ZIP blocks.

/// The zlib stream of `data`: miniz_oxide at level 4, what the `exr` crate uses.
pub(super) fn compress(data: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec_zlib(data, 4)
}
