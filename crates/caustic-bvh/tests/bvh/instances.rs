//! Two-level trees: the walks that enter instances (binary and four-wide) against brute force
//! over the world's triangles and, per instance, the prototype's triangles under the ray
//! carried into the instance's space (the same arithmetic the walks use, so the answers are
//! equal, not merely close).

use caustic_bvh::{BuildOptions, GpuBvh, Hit, InstanceInput, PrimitiveMotions, Prototype, Ray, build_instanced, closest_hit_brute_force, flatten_instanced};
use glam::{Mat4, Quat, Vec3};

use crate::{Rng, random_soup};

/// The closest hit by brute force: the world's triangles, then every instance's prototype.
fn brute_force(world: &[[Vec3; 3]], prototypes: &[Vec<[Vec3; 3]>], first_ids: &[u32], gpu: &GpuBvh, ray: &Ray) -> Option<Hit> {
    let mut best = closest_hit_brute_force(world, ray);
    for instance in &gpu.instances {
        let index = prototypes_of(gpu, instance.root);
        let limit = best.map_or(ray.t_max, |b| b.t);
        let object = instance.ray_to_object(&Ray { t_max: limit, ..*ray });
        if let Some(hit) = closest_hit_brute_force(&prototypes[index], &object) {
            best = Some(Hit { triangle: hit.triangle + first_ids[index], instance: Some(instance.index), ..hit });
        }
    }
    best
}

/// The prototype whose tree starts at binary node `root` (roots are in prototype order).
fn prototypes_of(gpu: &GpuBvh, root: u32) -> usize {
    let mut roots: Vec<u32> = gpu.instances.iter().map(|i| i.root).collect();
    roots.sort_unstable();
    roots.dedup();
    roots.iter().position(|&r| r == root).expect("a prototype root")
}

#[test]
fn walks_into_instances_agree_with_brute_force() {
    let mut rng = Rng::new(31);
    let world = random_soup(&mut rng, 300);
    let prototypes: Vec<Vec<[Vec3; 3]>> = vec![random_soup(&mut rng, 400).iter().map(|t| t.map(|v| v * 0.1)).collect(), random_soup(&mut rng, 50)];
    let first_ids = [world.len() as u32, (world.len() + prototypes[0].len()) as u32];
    let inputs: Vec<Prototype> = prototypes.iter().zip(first_ids).map(|(p, first_id)| Prototype { triangles: p, first_id }).collect();
    let mut instances = Vec::new();
    for i in 0..40 {
        let rotation = Quat::from_axis_angle(rng.direction(), rng.range(0.0, 6.0));
        let mut scale = Vec3::new(rng.range(0.3, 2.0), rng.range(0.3, 2.0), rng.range(0.3, 2.0));
        if i % 5 == 0 {
            scale.x = -scale.x;
        }
        let at = Vec3::new(rng.range(-12.0, 12.0), rng.range(-12.0, 12.0), rng.range(-12.0, 12.0));
        instances.push(InstanceInput {
            prototype: (i % 3 == 0) as u32,
            object_to_world: Mat4::from_scale_rotation_translation(scale, rotation, at),
            material: None,
        });
    }
    let moving = PrimitiveMotions::default();
    let build = build_instanced(&world, &[], &moving, &inputs, &instances, &BuildOptions::default());
    let gpu = flatten_instanced(&build, &world, &[], &moving, &inputs, &instances);
    let wide = gpu.to_wide().expect("a wide form");
    let exact = gpu.to_wide_exact().expect("an exact wide form");
    assert_eq!(gpu.instances.len(), 40);
    let (mut hits, mut in_instances, mut mirrored) = (0, 0, 0);
    for _ in 0..3000 {
        let origin = Vec3::new(rng.range(-15.0, 15.0), rng.range(-15.0, 15.0), rng.range(-15.0, 15.0));
        let ray = Ray { origin, direction: rng.direction(), t_max: f32::INFINITY };
        let truth = brute_force(&world, &prototypes, &first_ids, &gpu, &ray);
        for (walk, found, any) in [
            ("binary", gpu.closest_hit(&ray), gpu.any_hit(&ray)),
            ("wide", gpu.closest_hit_wide(&wide, &ray), gpu.any_hit_wide(&wide, &ray)),
            ("wide-exact", gpu.closest_hit_wide(&exact, &ray), gpu.any_hit_wide(&exact, &ray)),
        ] {
            assert_eq!(any, truth.is_some(), "{walk}: any hit for {ray:?}");
            match (found, truth) {
                (Some(f), Some(t)) => {
                    assert_eq!(f.t, t.t, "{walk}: {f:?} against {t:?} for {ray:?}");
                    if f.triangle == t.triangle {
                        assert_eq!((f.u, f.v, f.instance), (t.u, t.v, t.instance), "{walk}: for {ray:?}");
                    }
                }
                (f, t) => assert_eq!(f, t, "{walk}: for {ray:?}"),
            }
        }
        if let Some(hit) = truth {
            hits += 1;
            if let Some(instance) = hit.instance {
                in_instances += 1;
                mirrored += usize::from(instances[instance as usize].object_to_world.determinant() < 0.0);
            }
        }
    }
    println!("3000 rays: {hits} hits, {in_instances} on instances ({mirrored} mirrored); {} nodes", gpu.nodes.len());
    assert!(in_instances > 300 && mirrored > 30 && hits - in_instances > 150, "the rays meet the world, instances and mirrored ones");
}

/// Instances are alone in their leaves, every prototype tree is stored once however many
/// instances place it, and a tree of one prototype placed 10,000 times stays small.
#[test]
fn instances_share_their_prototype_and_sit_alone_in_leaves() {
    let mut rng = Rng::new(5);
    let prototype = random_soup(&mut rng, 2000);
    let inputs = [Prototype { triangles: &prototype, first_id: 0 }];
    let instances: Vec<InstanceInput> = (0..10_000)
        .map(|i| InstanceInput {
            prototype: 0,
            object_to_world: Mat4::from_translation(Vec3::new((i % 100) as f32 * 30.0, 0.0, (i / 100) as f32 * 30.0)),
            material: None,
        })
        .collect();
    let moving = PrimitiveMotions::default();
    let start = std::time::Instant::now();
    let build = build_instanced(&[], &[], &moving, &inputs, &instances, &BuildOptions::default());
    let gpu = flatten_instanced(&build, &[], &[], &moving, &inputs, &instances);
    println!(
        "10,000 instances of 2,000 triangles: {} nodes, {} records, built in {:.1} ms",
        gpu.nodes.len(),
        gpu.triangles.len(),
        start.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!(gpu.triangles.len(), 10_000 + 2000, "one record per instance and the prototype's triangles once");
    assert!(gpu.instances.iter().all(|i| i.root == gpu.instances[0].root));
    for node in &gpu.nodes {
        for word in [node.child0, node.child1] {
            if word & caustic_bvh::LEAF_BIT != 0 && word != caustic_bvh::EMPTY_CHILD {
                let (first, count) = caustic_bvh::decode_leaf(word);
                let records = &gpu.triangles[first as usize..(first + count) as usize];
                if records.iter().any(|r| r.id & caustic_bvh::INSTANCE_BIT != 0) {
                    assert_eq!(count, 1, "an instance shares its leaf");
                }
            }
        }
    }
}
