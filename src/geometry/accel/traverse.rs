//! Single-ray traversal of the 8-wide BVH: all eight child boxes of a node tested at once
//! (one AVX2 register per box plane; two SSE2 halves or a scalar loop where AVX2 is missing),
//! hit children visited near to far, the others kept on a small fixed stack with their entry
//! distance so that a closer hit found meanwhile discards them when they are popped.
//!
//! The box test is the slab test with the reciprocal direction, computed as (plane − origin) ×
//! (1/d), and the exit distance scaled up by [`FAR_SCALE`]: Ize, "Robust BVH ray traversal",
//! JCGT 2(2), 2013 shows that (1 + 2γ₃) makes this f32 test conservative (no box that the ray
//! touches is culled by rounding); the scale here is 1 + 2⁻²⁰ ≈ 1 + 9.5·10⁻⁷ > 1 + 2γ₃ ≈ 1 + 3.6·10⁻⁷,
//! and since the current closest distance is scaled with it, a triangle whose own f32 distance
//! is a few ulps below its box's computed entry is still reached. Nothing is culled near the
//! origin (obvhs's CWBVH culled boxes left within 10⁻⁴ units of it), and a direction
//! component of 0 is replaced by ±10⁻¹⁸ before taking its reciprocal, as Embree's `rcp_safe`
//! does, so no box test sees ∞·0.
//!
//! Near-to-far order with a per-ray sort of the hit children, single-ray SIMD over the
//! children: Wald, Benthin & Boulos, "Getting rid of packets", IEEE RT 2008; Dammertz, Hanika
//! & Keller, "Shallow bounding volume hierarchies for fast SIMD ray tracing of incoherent
//! rays", EGSR 2008; Embree's BVH8 single-ray traversal (Wald et al., ACM TOG 33(4), 2014).

use std::mem::MaybeUninit;

use super::build::{leaf_range, ChildRef, Node, WideBvh, LEAF_BIT, WIDTH};
use super::triangles::{Ray, TrianglePacket};

/// Relative margin on every box exit and on the current closest distance (see the module
/// documentation).
pub(super) const FAR_SCALE: f32 = 1.0 + 1.0 / 1_048_576.0;

/// Smallest direction component magnitude used for the reciprocal (Embree's `min_rcp_input`).
const MIN_DIR: f32 = 1e-18;

/// Stack entries kept on the call stack; a deeper BVH (a pathological scene) gets a heap stack.
pub(super) const STACK: usize = 256;

/// Which node test the CPU runs, detected once per BVH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Simd {
    /// AVX2: eight boxes per instruction.
    Avx2,
    /// SSE2 (every x86-64 CPU): two halves of four.
    Sse2,
    /// A plain loop (other architectures; tests everywhere).
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    Scalar,
}

impl Simd {
    pub fn detect() -> Simd {
        #[cfg(target_arch = "x86_64")]
        {
            if is_x86_feature_detected!("avx2") {
                Simd::Avx2
            } else {
                Simd::Sse2
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            Simd::Scalar
        }
    }

    /// Every variant this CPU can run (for tests).
    #[cfg(test)]
    pub fn available() -> Vec<Simd> {
        let mut v = vec![Simd::Scalar];
        #[cfg(target_arch = "x86_64")]
        {
            v.push(Simd::Sse2);
            if is_x86_feature_detected!("avx2") {
                v.push(Simd::Avx2);
            }
        }
        v
    }
}

/// What a query does at the leaves.
pub(super) trait Visitor {
    /// Whether hit children are visited near to far (closest-hit queries) or in slot order
    /// (any-hit queries, which stop at the first hit).
    const ORDERED: bool;
    /// Boxes entered beyond this distance (times [`FAR_SCALE`]) are skipped.
    fn bound(&self) -> f32;
    /// Tests a leaf's `packets`, the first of which is packet `first` of the BVH; `true` ends
    /// the traversal.
    fn leaf(&mut self, packets: &[TrianglePacket], first: usize) -> bool;
}

/// The ray's per-traversal constants.
pub(super) struct Prepared {
    pub origin: [f32; 3],
    pub inv: [f32; 3],
    /// Plane index (into `Node::planes`) of the near and far side per axis.
    near: [usize; 3],
    far: [usize; 3],
    pub t_min: f32,
}

impl Prepared {
    pub fn new(ray: &Ray) -> Prepared {
        let mut inv = [0.0; 3];
        let mut near = [0; 3];
        let mut far = [0; 3];
        for a in 0..3 {
            let d = ray.dir[a];
            let d = if d.abs() < MIN_DIR {
                MIN_DIR.copysign(d)
            } else {
                d
            };
            inv[a] = 1.0 / d;
            (near[a], far[a]) = if inv[a] >= 0.0 {
                (2 * a, 2 * a + 1)
            } else {
                (2 * a + 1, 2 * a)
            };
        }
        Prepared {
            origin: ray.origin,
            inv,
            near,
            far,
            t_min: ray.t_min,
        }
    }
}

/// Runs `visitor` over the BVH along `ray`.
pub(super) fn traverse<V: Visitor>(bvh: &WideBvh, simd: Simd, ray: &Ray, visitor: &mut V) {
    let p = Prepared::new(ray);
    with_stack(bvh, |stack| dispatch(bvh, simd, &p, visitor, stack));
}

/// Runs `f` with a traversal stack of `bvh.max_stack` entries: on the call stack ([`STACK`]
/// entries), or on the heap for a deeper BVH (a pathological scene).
#[inline(always)]
pub(super) fn with_stack<R>(
    bvh: &WideBvh,
    f: impl FnOnce(&mut [MaybeUninit<(ChildRef, f32)>]) -> R,
) -> R {
    if bvh.max_stack <= STACK {
        f(&mut [const { MaybeUninit::<(ChildRef, f32)>::uninit() }; STACK])
    } else {
        f(&mut vec![
            MaybeUninit::<(ChildRef, f32)>::uninit();
            bvh.max_stack
        ])
    }
}

fn dispatch<V: Visitor>(
    bvh: &WideBvh,
    simd: Simd,
    p: &Prepared,
    visitor: &mut V,
    stack: &mut [MaybeUninit<(ChildRef, f32)>],
) {
    assert!(stack.len() >= bvh.max_stack);
    match simd {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Simd::Avx2` is only chosen where the CPU has AVX2; the stack is deep enough.
        Simd::Avx2 => unsafe { run_avx2(bvh, p, visitor, stack) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the stack is deep enough (asserted above).
        Simd::Sse2 => unsafe { run_loop::<Sse2Boxes, V>(bvh, p, visitor, stack) },
        // SAFETY: the stack is deep enough (asserted above).
        _ => unsafe { run_loop::<ScalarBoxes, V>(bvh, p, visitor, stack) },
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<V: Visitor>(
    bvh: &WideBvh,
    p: &Prepared,
    visitor: &mut V,
    stack: &mut [MaybeUninit<(ChildRef, f32)>],
) {
    run_loop::<Avx2Boxes, V>(bvh, p, visitor, stack)
}

/// The eight-box test.
pub(super) trait BoxTest {
    /// What is tested: one ray ([`Prepared`]) or a bundle of rays (`bundle::Bundle`).
    type Rays;
    /// Writes the entry distances of the children into `t_near` and returns the mask of
    /// children whose box the ray meets within [t_min, bound·FAR_SCALE].
    ///
    /// # Safety
    /// The CPU must support the instructions the implementation uses.
    unsafe fn test(node: &Node, p: &Self::Rays, bound: f32, t_near: &mut [f32; WIDTH]) -> u32;
}

struct ScalarBoxes;

impl BoxTest for ScalarBoxes {
    type Rays = Prepared;
    #[inline(always)]
    unsafe fn test(node: &Node, p: &Prepared, bound: f32, t_near: &mut [f32; WIDTH]) -> u32 {
        let mut mask = 0;
        for (i, tn_out) in t_near.iter_mut().enumerate() {
            let mut tn = p.t_min;
            let mut tf = bound;
            for a in 0..3 {
                tn = tn.max((node.planes[p.near[a]][i] - p.origin[a]) * p.inv[a]);
                tf = tf.min((node.planes[p.far[a]][i] - p.origin[a]) * p.inv[a]);
            }
            *tn_out = tn;
            if tn <= tf * FAR_SCALE {
                mask |= 1 << i;
            }
        }
        mask
    }
}

#[cfg(target_arch = "x86_64")]
struct Sse2Boxes;

#[cfg(target_arch = "x86_64")]
impl BoxTest for Sse2Boxes {
    type Rays = Prepared;
    #[inline(always)]
    unsafe fn test(node: &Node, p: &Prepared, bound: f32, t_near: &mut [f32; WIDTH]) -> u32 {
        use std::arch::x86_64::*;
        let mut mask = 0;
        for half in 0..2 {
            let off = 4 * half;
            // SAFETY (indices): `Prepared` holds plane indices below 6 only.
            let ld = |plane: usize| _mm_load_ps(node.planes.get_unchecked(plane).as_ptr().add(off));
            let slab = |a: usize, plane: usize| {
                _mm_mul_ps(
                    _mm_sub_ps(ld(plane), _mm_set1_ps(p.origin[a])),
                    _mm_set1_ps(p.inv[a]),
                )
            };
            let tn = _mm_max_ps(
                _mm_max_ps(slab(0, p.near[0]), slab(1, p.near[1])),
                _mm_max_ps(slab(2, p.near[2]), _mm_set1_ps(p.t_min)),
            );
            let tf = _mm_mul_ps(
                _mm_min_ps(
                    _mm_min_ps(slab(0, p.far[0]), slab(1, p.far[1])),
                    _mm_min_ps(slab(2, p.far[2]), _mm_set1_ps(bound)),
                ),
                _mm_set1_ps(FAR_SCALE),
            );
            _mm_storeu_ps(t_near.as_mut_ptr().add(off), tn);
            mask |= (_mm_movemask_ps(_mm_cmple_ps(tn, tf)) as u32) << off;
        }
        mask
    }
}

#[cfg(target_arch = "x86_64")]
struct Avx2Boxes;

#[cfg(target_arch = "x86_64")]
impl BoxTest for Avx2Boxes {
    type Rays = Prepared;
    #[inline(always)]
    unsafe fn test(node: &Node, p: &Prepared, bound: f32, t_near: &mut [f32; WIDTH]) -> u32 {
        use std::arch::x86_64::*;
        // SAFETY (indices): `Prepared` holds plane indices below 6 only.
        let ld = |plane: usize| _mm256_load_ps(node.planes.get_unchecked(plane).as_ptr());
        let slab = |a: usize, plane: usize| {
            _mm256_mul_ps(
                _mm256_sub_ps(ld(plane), _mm256_set1_ps(p.origin[a])),
                _mm256_set1_ps(p.inv[a]),
            )
        };
        let tn = _mm256_max_ps(
            _mm256_max_ps(slab(0, p.near[0]), slab(1, p.near[1])),
            _mm256_max_ps(slab(2, p.near[2]), _mm256_set1_ps(p.t_min)),
        );
        let tf = _mm256_mul_ps(
            _mm256_min_ps(
                _mm256_min_ps(slab(0, p.far[0]), slab(1, p.far[1])),
                _mm256_min_ps(slab(2, p.far[2]), _mm256_set1_ps(bound)),
            ),
            _mm256_set1_ps(FAR_SCALE),
        );
        _mm256_storeu_ps(t_near.as_mut_ptr(), tn);
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32
    }
}

/// Asks for child `c`'s node or first packet (224 or 208 bytes) to be brought into the cache:
/// a child pushed on the stack is popped later, after its nearer siblings, and its cache misses
/// (a 1M-triangle BVH does not fit in L2) overlap theirs meanwhile.
#[inline(always)]
unsafe fn prefetch_child(bvh: &WideBvh, c: ChildRef) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = if c & LEAF_BIT == 0 {
            (bvh.nodes.as_ptr() as *const i8).add(c as usize)
        } else {
            bvh.packets.as_ptr().add(leaf_range(c).0) as *const i8
        };
        for off in [0, 64, 128, 192] {
            _mm_prefetch::<_MM_HINT_T0>(p.add(off));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (bvh, c);
}

/// The traversal loop.
///
/// # Safety
/// `B` must be runnable on this CPU and `stack` must hold `bvh.max_stack` entries.
#[inline(always)]
pub(super) unsafe fn run_loop<B: BoxTest, V: Visitor>(
    bvh: &WideBvh,
    p: &B::Rays,
    visitor: &mut V,
    stack: &mut [MaybeUninit<(ChildRef, f32)>],
) {
    let mut sp = 0usize;
    let mut cur: ChildRef = 0;
    let mut t_near = [0.0f32; WIDTH];
    loop {
        if cur & LEAF_BIT == 0 {
            // SAFETY: inner references are byte offsets of nodes in `bvh.nodes` (`build`).
            let node = &*(bvh.nodes.as_ptr() as *const u8)
                .add(cur as usize)
                .cast::<Node>();
            let mut mask = B::test(node, p, visitor.bound(), &mut t_near);
            if mask != 0 {
                // `& 7`: the mask has eight bits, and the index then needs no bounds check.
                let first = mask.trailing_zeros() as usize & 7;
                mask &= mask - 1;
                if mask == 0 {
                    cur = node.children[first];
                    continue;
                }
                if !V::ORDERED {
                    cur = node.children[first];
                    while mask != 0 {
                        let i = mask.trailing_zeros() as usize & 7;
                        mask &= mask - 1;
                        prefetch_child(bvh, node.children[i]);
                        stack
                            .get_unchecked_mut(sp)
                            .write((node.children[i], t_near[i]));
                        sp += 1;
                    }
                    continue;
                }
                let second = mask.trailing_zeros() as usize & 7;
                mask &= mask - 1;
                if mask == 0 {
                    // Two children (the commonest case after one): nearer one next, the other
                    // pushed, without the sort's round trip through the stack.
                    let (near, far) = if t_near[second] < t_near[first] {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    prefetch_child(bvh, node.children[far]);
                    stack
                        .get_unchecked_mut(sp)
                        .write((node.children[far], t_near[far]));
                    sp += 1;
                    cur = node.children[near];
                    continue;
                }
                // Three or more: push every hit child, then sort the pushed run so that the
                // nearest is on top (insertion sort of at most eight entries).
                let base = sp;
                for i in [first, second] {
                    prefetch_child(bvh, node.children[i]);
                    let e = (node.children[i], t_near[i]);
                    if sp > base && stack.get_unchecked(sp - 1).assume_init().1 < e.1 {
                        let prev = stack.get_unchecked(sp - 1).assume_init();
                        stack.get_unchecked_mut(sp - 1).write(e);
                        stack.get_unchecked_mut(sp).write(prev);
                    } else {
                        stack.get_unchecked_mut(sp).write(e);
                    }
                    sp += 1;
                }
                while mask != 0 {
                    let i = mask.trailing_zeros() as usize & 7;
                    mask &= mask - 1;
                    prefetch_child(bvh, node.children[i]);
                    let e = (node.children[i], t_near[i]);
                    let mut j = sp;
                    while j > base && stack.get_unchecked(j - 1).assume_init().1 < e.1 {
                        let prev = stack.get_unchecked(j - 1).assume_init();
                        stack.get_unchecked_mut(j).write(prev);
                        j -= 1;
                    }
                    stack.get_unchecked_mut(j).write(e);
                    sp += 1;
                }
                sp -= 1;
                cur = stack.get_unchecked(sp).assume_init().0;
                continue;
            }
        } else {
            let (first, count) = leaf_range(cur);
            if visitor.leaf(&bvh.packets[first..first + count], first) {
                return;
            }
        }
        // Pop the nearest pending child that may still hold something closer.
        loop {
            if sp == 0 {
                return;
            }
            sp -= 1;
            let (c, t) = stack.get_unchecked(sp).assume_init();
            if t <= visitor.bound() * FAR_SCALE {
                cur = c;
                break;
            }
        }
    }
}
