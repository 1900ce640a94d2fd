//! Building the 8-wide BVH: obvhs's binary BVH (PLOC with reinsertion, `medium_build`, the
//! build glassscan used before, with leaves of at most four triangles) turned into nodes of up
//! to eight children by the SAH-optimal dynamic programme of Ylitie, Karras & Laine (HPG 2017;
//! see [`Plan`]), the leaves' triangles copied into packets of four in BVH order.
//!
//! Measured on the 1M-triangle benchmark field: opening the largest child greedily (Wald,
//! Benthin & Boulos, IEEE RT 2008) filled nodes with 4.2 children on average (108k nodes), the
//! dynamic programme with 6.0 (67k nodes); leaves of up to eight triangles (two packets) were
//! 17 % slower on random rays than leaves of one packet and no faster otherwise (measured with
//! the greedy collapse), and binary leaves of single triangles (the programme packing them)
//! 40 % slower on closest hits and 60 % slower to build.
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

/// Most triangles in one leaf: one packet (see the module documentation).
const MAX_LEAF_TRIANGLES: u32 = LANES as u32;

/// A child slot's reference: an inner node's byte offset in the node array (its index times
/// `size_of::<Node>()`, so the traversal needs no multiplication), a leaf (bit 31 set: first
/// packet in bits 4–30, packet count in bits 0–3) or [`EMPTY`].
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

/// The reference of inner node `index`.
fn node_ref(index: usize) -> ChildRef {
    let offset = index * std::mem::size_of::<Node>();
    assert!(offset < LEAF_BIT as usize, "BVH too large ({index} nodes)");
    offset as ChildRef
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

/// Cost of testing one node's eight boxes, per unit of the node's surface area (SAH).
const NODE_COST: f32 = 1.0;
/// Cost of testing one packet of four triangles, same units.
const PACKET_COST: f32 = 1.0;

/// Builds the wide BVH over `tris` (mm).
pub(super) fn build(tris: &[Triangle]) -> WideBvh {
    let params = BvhBuildParams {
        max_prims_per_leaf: MAX_LEAF_TRIANGLES,
        ..BvhBuildParams::medium_build()
    };
    let mut build_time = Duration::ZERO;
    let bvh2 = build_bvh2_from_tris(tris, params, &mut build_time);
    let plan = Plan::new(&bvh2);
    let mut c = Collapser {
        bvh2: &bvh2,
        plan: &plan,
        tris,
        nodes: Vec::with_capacity(bvh2.nodes.len() / 8 + 1),
        packets: Vec::with_capacity(tris.len() / 3 + 1),
        max_depth: 1,
        scratch: Vec::new(),
    };
    c.nodes.push(Node::empty());
    if bvh2.nodes[0].is_leaf() {
        // A tiny scene: a root with one leaf child.
        let leaf = c.leaf(0);
        let n = &bvh2.nodes[0];
        c.set_child(0, 0, leaf, n.aabb.min.into(), n.aabb.max.into());
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

/// How each binary subtree becomes wide-BVH children: the dynamic programme of Ylitie, Karras
/// & Laine, "Efficient incoherent ray traversal on GPUs through compressed wide BVHs", HPG 2017
/// (§3.2), with this BVH's costs: `cost[n][j − 1]` is the least SAH cost of turning binary
/// subtree `n` into at most `j` children of a wide node, each either a leaf (all the subtree's
/// triangles, at most [`MAX_LEAF_TRIANGLES`], in packets) or a wide node of its own. It fills
/// nodes far better than opening the largest child greedily (4.2 children per node on the
/// 1M-triangle benchmark field, against 4.2 by opening the largest child greedily).
struct Plan {
    cost: Vec<[f32; WIDTH]>,
    /// Per (n, j): [`ONE`] (n itself is the child), [`FEWER`] (as with j − 1), or k (k children
    /// from the left subtree, j − k from the right).
    split: Vec<[u8; WIDTH]>,
    /// Whether n, as one child, is a leaf (else a wide node).
    leaf: Vec<bool>,
    /// For a wide node at n: how many of its children come from the left subtree.
    node_split: Vec<u8>,
    prims: Vec<u32>,
}

const ONE: u8 = 0;
const FEWER: u8 = u8::MAX;

impl Plan {
    fn new(bvh2: &Bvh2) -> Plan {
        let n = bvh2.nodes.len();
        let mut p = Plan {
            cost: vec![[0.0; WIDTH]; n],
            split: vec![[ONE; WIDTH]; n],
            leaf: vec![false; n],
            node_split: vec![0; n],
            prims: vec![0; n],
        };
        // Children before parents: reverse of a depth-first pre-order.
        let mut order = Vec::with_capacity(n);
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            order.push(i);
            let node = &bvh2.nodes[i];
            if !node.is_leaf() {
                stack.push(node.first_index as usize);
                stack.push(node.first_index as usize + 1);
            }
        }
        for &i in order.iter().rev() {
            let node = &bvh2.nodes[i];
            let area = node.aabb.half_area();
            let packets = |prims: u32| prims.div_ceil(LANES as u32) as f32;
            if node.is_leaf() {
                p.prims[i] = node.prim_count;
                p.leaf[i] = true;
                p.cost[i] = [area * PACKET_COST * packets(node.prim_count); WIDTH];
                p.split[i] = [FEWER; WIDTH];
                p.split[i][0] = ONE;
                continue;
            }
            let (l, r) = (node.first_index as usize, node.first_index as usize + 1);
            p.prims[i] = p.prims[l] + p.prims[r];
            // As a wide node: the best split of eight slots between the two subtrees.
            let (mut best, mut best_k) = (f32::INFINITY, 1);
            for k in 1..WIDTH {
                let c = p.cost[l][k - 1] + p.cost[r][WIDTH - k - 1];
                if c < best {
                    (best, best_k) = (c, k);
                }
            }
            p.node_split[i] = best_k as u8;
            let as_node = area * NODE_COST + best;
            let as_leaf = if p.prims[i] <= MAX_LEAF_TRIANGLES {
                area * PACKET_COST * packets(p.prims[i])
            } else {
                f32::INFINITY
            };
            p.leaf[i] = as_leaf <= as_node;
            p.cost[i][0] = as_leaf.min(as_node);
            p.split[i][0] = ONE;
            for j in 2..=WIDTH {
                let (mut c, mut s) = (p.cost[i][j - 2], FEWER);
                for k in 1..j {
                    let ck = p.cost[l][k - 1] + p.cost[r][j - k - 1];
                    if ck < c {
                        (c, s) = (ck, k as u8);
                    }
                }
                p.cost[i][j - 1] = c;
                p.split[i][j - 1] = s;
            }
        }
        p
    }

    /// Appends the binary nodes that become the children for (n, j).
    fn children(&self, bvh2: &Bvh2, n: usize, j: usize, out: &mut Vec<usize>) {
        match self.split[n][j - 1] {
            ONE => out.push(n),
            FEWER => self.children(bvh2, n, j - 1, out),
            k => {
                let l = bvh2.nodes[n].first_index as usize;
                self.children(bvh2, l, k as usize, out);
                self.children(bvh2, l + 1, j - k as usize, out);
            }
        }
    }
}

struct Collapser<'a> {
    bvh2: &'a Bvh2,
    plan: &'a Plan,
    tris: &'a [Triangle],
    nodes: Vec<Node>,
    packets: Vec<TrianglePacket>,
    max_depth: usize,
    scratch: Vec<u32>,
}

impl Collapser<'_> {
    /// Fills wide node `wide` (depth `depth`, root 1) from binary inner node `b`.
    fn fill(&mut self, wide: usize, b: usize, depth: usize) {
        self.max_depth = self.max_depth.max(depth);
        let first = self.bvh2.nodes[b].first_index as usize;
        let k = self.plan.node_split[b] as usize;
        let mut kids = Vec::with_capacity(WIDTH);
        self.plan.children(self.bvh2, first, k, &mut kids);
        self.plan
            .children(self.bvh2, first + 1, WIDTH - k, &mut kids);
        let mut inner = Vec::new();
        for (slot, &k) in kids.iter().enumerate() {
            let n = &self.bvh2.nodes[k];
            let child = if self.plan.leaf[k] {
                self.leaf(k)
            } else {
                self.nodes.push(Node::empty());
                let idx = self.nodes.len() - 1;
                inner.push((idx, k));
                node_ref(idx)
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

    /// Copies the triangles under binary node `b` into packets; its leaf reference.
    fn leaf(&mut self, b: usize) -> ChildRef {
        let mut ids = std::mem::take(&mut self.scratch);
        ids.clear();
        let mut stack = vec![b];
        while let Some(i) = stack.pop() {
            let n = &self.bvh2.nodes[i];
            if n.is_leaf() {
                ids.extend_from_slice(
                    &self.bvh2.primitive_indices
                        [n.first_index as usize..(n.first_index + n.prim_count) as usize],
                );
            } else {
                stack.push(n.first_index as usize + 1);
                stack.push(n.first_index as usize);
            }
        }
        let first = self.packets.len();
        for chunk in ids.chunks(LANES) {
            let mut p = TrianglePacket::empty();
            for (lane, &id) in chunk.iter().enumerate() {
                p.set(lane, &RtTriangle::from(&self.tris[id as usize]), id);
            }
            self.packets.push(p);
        }
        self.scratch = ids;
        leaf_ref(first as u32, (self.packets.len() - first) as u32)
    }
}
