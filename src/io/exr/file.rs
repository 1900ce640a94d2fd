//! The bytes of a single-part scanline OpenEXR file (OpenEXR File Layout, "High-Level
//! Layout", "Line Offset Table", "Scan Line Blocks"): magic number, version field and header
//! ([`super::header`]), the line offset table (one u64 a block: where the block starts,
//! counted from the start of the file), then the blocks in increasing y, each its first
//! scanline's y (i32), its stored size (i32) and its bytes ([`super::zip_block`]).
//!
//! Blocks are compressed in parallel; each one's bytes depend on its pixels alone and they are
//! laid out in y order, so the file does not depend on the number of threads.

use std::cell::RefCell;

use rayon::prelude::*;

use super::header::{self, Value};
use super::zip_block::{self, Samples, Scratch, LINES_PER_BLOCK};

thread_local! {
    /// Each thread's buffers (about 1 MB for glassscan's images), kept from file to file: fresh
    /// ones for every block cost page faults. What a block's bytes are does not depend on them.
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The file of a `width` × `height` image of f32 `channels` (Latin-1 name, samples), already
/// sorted by name, with the `extra` header attributes after the standard ones. The caller has
/// checked that the sizes fit the format ([`fits`]).
pub(super) fn encode(
    width: usize,
    height: usize,
    channels: &[(Vec<u8>, Samples)],
    extra: Vec<(&'static str, Value)>,
) -> Vec<u8> {
    let block_count = height.div_ceil(LINES_PER_BLOCK);
    let as_i32 = |v: usize| i32::try_from(v).expect("checked by fits()");
    let names = channels.iter().map(|(name, _)| name.clone()).collect();
    let mut attributes =
        header::standard_attributes(as_i32(width), as_i32(height), names, as_i32(block_count));
    attributes.extend(extra);
    let mut out = header::encode(&attributes);

    let samples: Vec<Samples> = channels.iter().map(|&(_, s)| s).collect();
    let blocks: Vec<Vec<u8>> = (0..block_count)
        .into_par_iter()
        .map(|b| {
            let rows = b * LINES_PER_BLOCK..((b + 1) * LINES_PER_BLOCK).min(height);
            SCRATCH.with_borrow_mut(|scratch| zip_block::encode(&samples, width, rows, scratch))
        })
        .collect();

    let table_len = 8 * block_count;
    let data_len: usize = blocks.iter().map(|b| 8 + b.len()).sum();
    out.reserve(table_len + data_len);
    let mut offset = (out.len() + table_len) as u64;
    for block in &blocks {
        out.extend_from_slice(&offset.to_le_bytes());
        offset += 8 + block.len() as u64;
    }
    for (b, block) in blocks.iter().enumerate() {
        out.extend_from_slice(&as_i32(b * LINES_PER_BLOCK).to_le_bytes());
        out.extend_from_slice(&as_i32(block.len()).to_le_bytes());
        out.extend_from_slice(block);
    }
    out
}

/// Whether a `width` × `height` image of `channel_count` f32 channels fits the format: the
/// data window's corners and every block's stored size are i32.
pub(super) fn fits(width: usize, height: usize, channel_count: usize) -> bool {
    let block_bytes = LINES_PER_BLOCK
        .checked_mul(width)
        .and_then(|v| v.checked_mul(channel_count))
        .and_then(|v| v.checked_mul(4));
    i32::try_from(width).is_ok()
        && i32::try_from(height).is_ok()
        && block_bytes.is_some_and(|v| i32::try_from(v).is_ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_beyond_the_formats_i32_fields_do_not_fit() {
        assert!(fits(640, 832, 12));
        assert!(fits(i32::MAX as usize / 64, 1, 1));
        assert!(!fits(i32::MAX as usize / 64 + 1, 1, 1));
        assert!(!fits(1, i32::MAX as usize + 1, 1));
        assert!(!fits(usize::MAX, 1, 1));
        assert!(!fits(1 << 20, 1, 1 << 20));
    }
}
