//! Trees holding triangles and analytic shapes (spheres, disks, boxes, planes) give exactly
//! the brute-force closest hit.

use crate::Rng;
use caustic_bvh::{
    BuildOptions, GpuShape, Ray, SHAPE_BIT, ShapeInput, ShapeKind, build_with_shapes, closest_hit_brute_force, flatten_with_shapes, intersect_shape,
};
use glam::{Mat4, Quat, Vec3};

fn random_shapes(rng: &mut Rng, count: usize) -> Vec<ShapeInput> {
    let kinds = [ShapeKind::Sphere, ShapeKind::Disk, ShapeKind::Box];
    let mut shapes: Vec<ShapeInput> = (0..count)
        .map(|_| {
            let kind = kinds[rng.index(kinds.len())];
            let scale = Vec3::new(rng.range(0.05, 1.0), rng.range(0.05, 1.0), rng.range(0.05, 1.0));
            let rotation = Quat::from_axis_angle(rng.direction(), rng.range(0.0, 6.3));
            let position = Vec3::new(rng.range(-10.0, 10.0), rng.range(-10.0, 10.0), rng.range(-10.0, 10.0));
            ShapeInput { kind, object_to_world: Mat4::from_scale_rotation_translation(scale, rotation, position) }
        })
        .collect();
    let floor = Mat4::from_translation(Vec3::new(0.0, -12.0, 0.0)) * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    shapes.insert(count / 2, ShapeInput { kind: ShapeKind::Plane, object_to_world: floor });
    shapes
}

/// Closest hit over triangles and shapes by testing every primitive.
fn brute_force(triangles: &[[Vec3; 3]], shapes: &[ShapeInput], ray: &Ray) -> Option<(f32, u32)> {
    let mut best = closest_hit_brute_force(triangles, ray).map(|h| (h.t, h.triangle));
    for (i, input) in shapes.iter().enumerate() {
        let limit = Ray { t_max: best.map_or(ray.t_max, |b| b.0), ..*ray };
        if let Some(t) = intersect_shape(&limit, &GpuShape::new(input, i as u32)) {
            best = Some((t, SHAPE_BIT | i as u32));
        }
    }
    best
}

#[test]
fn mixed_trees_match_brute_force() {
    let mut rng = Rng::new(11);
    let triangles: Vec<[Vec3; 3]> = (0..500)
        .map(|_| {
            let c = Vec3::new(rng.range(-10.0, 10.0), rng.range(-10.0, 10.0), rng.range(-10.0, 10.0));
            [c, c + rng.direction(), c + rng.direction()]
        })
        .collect();
    let shapes = random_shapes(&mut rng, 300);
    let bvh = build_with_shapes(&triangles, &shapes, &BuildOptions::default());
    let gpu = flatten_with_shapes(&bvh, &triangles, &shapes);
    assert_eq!(gpu.shapes.len(), shapes.len());
    assert_eq!(gpu.first_plane as usize, shapes.len() - 1);
    let (mut hits, mut shape_hits, mut mismatches) = (0, 0, 0);
    for _ in 0..20_000 {
        let ray =
            Ray { origin: Vec3::new(rng.range(-15.0, 15.0), rng.range(-15.0, 15.0), rng.range(-15.0, 15.0)), direction: rng.direction(), t_max: f32::INFINITY };
        let tree = gpu.closest_hit(&ray).map(|h| (h.t, h.triangle));
        let brute = brute_force(&triangles, &shapes, &ray);
        hits += usize::from(brute.is_some());
        shape_hits += usize::from(brute.is_some_and(|b| b.1 & SHAPE_BIT != 0));
        if tree != brute {
            mismatches += 1;
        }
        assert_eq!(tree.is_some(), gpu.any_hit(&ray), "any_hit disagrees on {ray:?}");
    }
    println!("mixed tree: 20000 rays, {hits} hits ({shape_hits} on shapes), {mismatches} differ from brute force");
    assert_eq!(mismatches, 0);
}
