//! Building the 8-wide BVH: obvhs's binary BVH (PLOC with reinsertion, `medium_build`, the
//! build glassscan used before) collapsed into nodes of up to eight children, with the leaves'
//! triangles copied into packets of four in BVH order.
//!
//! Collapse: a wide node takes a binary node's two children and keeps opening the inner child
//! with the largest surface area until it has eight children or only leaves (the greedy rule
//! of Wald, Benthin & Boulos, "Getting rid of packets", IEEE RT 2008, and of Embree's BVH4/8
//! builders: a ray is likeliest to enter the largest box, so its children are pulled up first).
//!
//! Units: millimetres.

use std::time::Duration;

use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::bvh2::Bvh2;
use obvhs::rt_triangle::RtTriangle;
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;

use super::triangles::{TrianglePacket, LANES};

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// Most triangles in one binary leaf: one packet (see `build`).
const MAX_LEAF_TRIANGLES: u32 = LANES as u32;

/// A child slot's reference: an inner node's index, a leaf (bit 31 set: first packet in bits
/// 4–30, packet count in bits 0–3) or [`EMPTY`].
pub(super) type ChildRef = u32;

/// An unused child slot (its box is empty, so no ray enters it).
pub(super) const EMPTY: ChildRef = u32::MAX;
pub(super) const LEAF_BIT: u32 = 1 << 31;
const MAX_PACKETS_PER_LEAF: u32 = 15;
const MAX_FIRST_PACKET: u32 = (1 << 27) - 1;

pub(super) fn leaf_ref(first_packet: u32, count: u32) -> ChildRef {
    assert!(
        (1..=MAX_PACKETS_PER_LEAF).contains(&count) && first_packet <= MAX_FIRST_PACKET,
        "BVH leaf out of range ({count} packets from {first_packet})"
    );
    LEAF_BIT | (first_packet << 4) | count
}

/// (first packet, packet count) of a leaf reference.
#[inline(always)]
pub(super) fn leaf_range(r: ChildRef) -> (usize, usize) {
    (((r & !LEAF_BIT) >> 4) as usize, (r & 0xF) as usize)
}

/// One node: the children's boxes as structure of arrays (min x, max x, min y, max y, min z,
/// max z; eight lanes each, so one AVX register per plane) and their references. 224 bytes,
/// aligned to 32 so the loads are aligned.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Node {
    pub planes: [[f32; WIDTH]; 6],
    pub children: [ChildRef; WIDTH],
}

impl Node {
    fn empty() -> Node {
        let mut planes = [[0.0; WIDTH]; 6];
        for axis in 0..3 {
            planes[2 * axis] = [f32::INFINITY; WIDTH];
            planes[2 * axis + 1] = [f32::NEG_INFINITY; WIDTH];
        }
        Node {
            planes,
            children: [EMPTY; WIDTH],
        }
    }
}

/// The wide BVH: node 0 is the root.
pub(super) struct WideBvh {
    pub nodes: Vec<Node>,
    pub packets: Vec<TrianglePacket>,
    /// Stack entries the traversal needs at most: depth·(WIDTH − 1) + 1 (each inner node on
    /// the way down pushes at most WIDTH − 1 children).
    pub max_stack: usize,
}

/// Builds the wide BVH over `tris` (mm).
pub(super) fn build(tris: &[Triangle]) -> WideBvh {
    // Leaves of at most one packet: measured against obvhs's default of 8 triangles per leaf
    // (two packets), which is slower on every benchmark (see benches/README.md).
    let params = BvhBuildParams {
        max_prims_per_leaf: MAX_LEAF_TRIANGLES,
        ..BvhBuildParams::medium_build()
    };
    let mut build_time = Duration::ZERO;
    let bvh2 = build_bvh2_from_tris(tris, params, &mut build_time);
    let mut c = Collapser {
        bvh2: &bvh2,
        tris,
        nodes: Vec::with_capacity(bvh2.nodes.len() / 4 + 1),
        packets: Vec::with_capacity(tris.len() / 2 + 1),
        max_depth: 0,
    };
    c.nodes.push(Node::empty());
    if bvh2.nodes[0].is_leaf() {
        // A tiny scene: a root with one leaf child.
        let leaf = c.leaf(0);
        let n = &bvh2.nodes[0];
        c.set_child(0, 0, leaf, n.aabb.min.into(), n.aabb.max.into());
        c.max_depth = 1;
    } else {
        c.fill(0, 0, 1);
    }
    let max_stack = c.max_depth * (WIDTH - 1) + 1;
    WideBvh {
        nodes: c.nodes,
        packets: c.packets,
        max_stack,
    }
}

struct Collapser<'a> {
    bvh2: &'a Bvh2,
    tris: &'a [Triangle],
    nodes: Vec<Node>,
    packets: Vec<TrianglePacket>,
    max_depth: usize,
}

impl Collapser<'_> {
    /// Fills wide node `wide` (depth `depth`, root 1) from binary inner node `b`.
    fn fill(&mut self, wide: usize, b: usize, depth: usize) {
        self.max_depth = self.max_depth.max(depth);
        let first = self.bvh2.nodes[b].first_index as usize;
        let mut kids: Vec<usize> = vec![first, first + 1];
        while kids.len() < WIDTH {
            // Open the inner child with the largest surface area.
            let best = kids
                .iter()
                .enumerate()
                .filter(|(_, &k)| !self.bvh2.nodes[k].is_leaf())
                .max_by(|(_, &a), (_, &b)| {
                    let (a, b) = (
                        self.bvh2.nodes[a].aabb.half_area(),
                        self.bvh2.nodes[b].aabb.half_area(),
                    );
                    a.total_cmp(&b)
                })
                .map(|(i, _)| i);
            let Some(i) = best else { break };
            let f = self.bvh2.nodes[kids[i]].first_index as usize;
            kids[i] = f;
            kids.push(f + 1);
        }
        let mut inner = Vec::new();
        for (slot, &k) in kids.iter().enumerate() {
            let n = &self.bvh2.nodes[k];
            let child = if n.is_leaf() {
                self.leaf(k)
            } else {
                self.nodes.push(Node::empty());
                let idx = self.nodes.len() - 1;
                inner.push((idx, k));
                idx as u32
            };
            self.set_child(wide, slot, child, n.aabb.min.into(), n.aabb.max.into());
        }
        // Children after their parent, each subtree contiguous (depth first).
        for (idx, k) in inner {
            self.fill(idx, k, depth + 1);
        }
    }

    fn set_child(&mut self, wide: usize, slot: usize, child: ChildRef, lo: [f32; 3], hi: [f32; 3]) {
        let node = &mut self.nodes[wide];
        for axis in 0..3 {
            node.planes[2 * axis][slot] = lo[axis];
            node.planes[2 * axis + 1][slot] = hi[axis];
        }
        node.children[slot] = child;
    }

    /// Copies binary leaf `b`'s triangles into packets; its reference.
    fn leaf(&mut self, b: usize) -> ChildRef {
        let n = &self.bvh2.nodes[b];
        let ids = &self.bvh2.primitive_indices
            [n.first_index as usize..(n.first_index + n.prim_count) as usize];
        let first = self.packets.len();
        for chunk in ids.chunks(LANES) {
            let mut p = TrianglePacket::empty();
            for (lane, &id) in chunk.iter().enumerate() {
                p.set(lane, &RtTriangle::from(&self.tris[id as usize]), id);
            }
            self.packets.push(p);
        }
        leaf_ref(first as u32, (self.packets.len() - first) as u32)
    }
}
