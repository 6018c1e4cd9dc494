//! Caustic's bounding volume hierarchy: plain arrays in, plain arrays out.
//!
//! In the spirit of tinybvh, the BVH is data without pointers, and each stage is its
//! own module:
//!
//! * [`build`] (module `build`, helped by `split`): a binned SAH builder producing a
//!   binary [`Bvh`] of [`Node`]s plus a triangle index array in leaf order.
//! * [`flatten`] (module `layout`): converts it into the GPU layout, [`GpuBvh`]: 64-byte
//!   [`GpuNode`]s holding both children's boxes, and [`GpuTriangle`]s gathered in leaf
//!   order. The WGSL renderer mirrors these structs and the child word encoding.
//! * [`GpuBvh::closest_hit`] / [`GpuBvh::any_hit`] (module `traverse`): the CPU twin of
//!   the WGSL traversal, checked against [`closest_hit_brute_force`] by the tests.
//! * [`intersect_triangle`] (module `triangle`): the watertight ray/triangle test both
//!   traversals use.
//!
//! ```
//! use caustic_bvh::{BuildOptions, Ray, build, flatten};
//! use glam::Vec3;
//!
//! let triangles = [[Vec3::ZERO, Vec3::X, Vec3::Y], [Vec3::Z, Vec3::X + Vec3::Z, Vec3::Y + Vec3::Z]];
//! let bvh = build(&triangles, &BuildOptions::default());
//! let gpu = flatten(&bvh, &triangles);
//! let ray = Ray { origin: Vec3::new(0.2, 0.2, 5.0), direction: Vec3::NEG_Z, t_max: f32::INFINITY };
//! let hit = gpu.closest_hit(&ray).unwrap();
//! assert_eq!((hit.triangle, hit.t), (1, 4.0));
//! ```

mod aabb;
mod build;
mod instance;
mod layout;
mod motion;
mod shape;
mod split;
mod traverse;
mod traverse_wide;
mod triangle;
mod wide;

pub use aabb::Aabb;
pub use build::{
    BuildOptions, BuildStats, Bvh, MAX_DEPTH, MAX_LEAF_SIZE, Node, SAH_INTERSECTION_COST, SAH_TRAVERSAL_COST, SplitMethod, build, build_with_shapes, sah_cost,
};
pub use instance::{GpuInstance, INSTANCE_BIT, INSTANCE_EXIT, INSTANCE_KIND, InstanceInput, InstancedBuild, Prototype, build_instanced, flatten_instanced};
pub use layout::{EMPTY_CHILD, GpuBvh, GpuNode, GpuTriangle, LEAF_BIT, MAX_TRIANGLES, decode_leaf, encode_leaf, flatten, flatten_with_shapes};
pub use motion::{GpuMotion, MAX_SAMPLED_STEPS, MAX_SAMPLED_TURN, PrimitiveMotions, build_with_motion, flatten_with_motion, shapes_and_motions};
pub use shape::{GpuShape, SHAPE_BIT, ShapeInput, ShapeKind, intersect_shape};
pub use split::MAX_BINS;
pub use traverse::{MIN_DIRECTION, ON_PLANE_EXIT, SLAB_EXIT_SCALE, STACK_SIZE};
pub use triangle::{Hit, Ray, closest_hit_brute_force, intersect_triangle, intersect_triangle_facing, unit_cube_triangles};
pub use wide::{GpuWideExactNode, GpuWideNode, WIDE_ARITY, WIDE_STACK_SIZE, WideError, WideNode, WideNodes};
