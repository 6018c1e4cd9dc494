//! Picking: which object and material a pixel shows, found by tracing the pixel's camera ray
//! on the CPU through the same triangles, shapes and BVH layout the kernels use
//! ([`caustic_gpu::SceneData`], [`caustic_bvh::GpuBvh::closest_hit`]).

use caustic_bvh::{BuildOptions, GpuBvh, Ray, SHAPE_BIT};
use caustic_gpu::SceneData;
use caustic_scene::{Camera, Light, Scene};
use glam::Vec3;

/// What a picked pixel shows.
#[derive(Clone, Debug, PartialEq)]
pub enum Picked {
    /// A triangle of mesh `mesh` (its index within the mesh is `triangle`).
    Mesh { mesh: usize, triangle: usize },
    /// Analytic shape `shape` of the scene.
    Shape { shape: usize },
    /// The quad light `light` (an index into the scene's lights).
    QuadLight { light: usize },
    /// Triangle `triangle` of the mesh that instance `instance` places.
    Instance { instance: usize, triangle: usize },
}

/// A pick: the object, its material (an index into the scene's materials, `None` for a quad
/// light, whose emitter is the light itself) and the hit distance along the ray.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// The object hit.
    pub picked: Picked,
    /// Its material in [`Scene::materials`], if it has one.
    pub material: Option<usize>,
    /// Distance from the eye.
    pub distance: f32,
}

/// The scene's geometry prepared for picking.
pub struct Picker {
    bvh: GpuBvh,
    /// Material of every device triangle (meshes, then two per quad light).
    triangle_materials: Vec<u32>,
    /// First device triangle of each mesh.
    mesh_starts: Vec<usize>,
    /// Scene light index of each quad light, in device order.
    quad_lights: Vec<usize>,
    /// Number of scene materials; device materials past it are quad-light emitters.
    scene_materials: usize,
    /// First device triangle of each instanced mesh (prototype).
    prototype_starts: Vec<usize>,
}

impl Picker {
    /// Builds a BVH over `scene` exactly as the device scene holds it (instances entered by
    /// the same two-level walk), with every object at shutter open.
    pub fn new(scene: &Scene) -> Picker {
        let data = SceneData::new(scene);
        let still = caustic_bvh::PrimitiveMotions::default();
        let (bvh, _) = caustic_gpu::build_bvh(&data, &still, &BuildOptions::default());
        let prototype_starts = data.prototypes.iter().map(|r| r.start).collect();
        let triangle_materials = data.shading[..data.triangles.len()].iter().map(|s| s.material).collect();
        let mut mesh_starts = Vec::with_capacity(scene.meshes.len());
        let mut start = 0;
        for mesh in &scene.meshes {
            mesh_starts.push(start);
            start += mesh.triangle_count();
        }
        let quad_lights = scene.lights.iter().enumerate().filter(|(_, l)| matches!(l, Light::Quad { .. })).map(|(i, _)| i).collect();
        Picker { bvh, triangle_materials, mesh_starts, quad_lights, scene_materials: scene.materials.len(), prototype_starts }
    }

    /// The object seen at `pixel` (in image pixels, origin top-left) of an image of
    /// `resolution` taken by `camera`, through the pixel's centre ray; `None` for the sky.
    pub fn pick(&self, scene: &Scene, camera: &Camera, resolution: (u32, u32), pixel: (f32, f32)) -> Option<Pick> {
        let (origin, direction) = camera_ray(camera, resolution, pixel);
        let ray = Ray { origin, direction, t_max: f32::INFINITY };
        let hit = self.bvh.closest_hit(&ray)?;
        if hit.triangle & SHAPE_BIT != 0 {
            let shape = (hit.triangle & !SHAPE_BIT) as usize;
            return Some(Pick { picked: Picked::Shape { shape }, material: Some(scene.shapes[shape].material as usize), distance: hit.t });
        }
        let triangle = hit.triangle as usize;
        if let Some(instance) = hit.instance.map(|i| i as usize) {
            let placed = &scene.instances[instance];
            let prototype = placed.prototype as usize;
            let material = placed.material.unwrap_or(scene.prototypes[prototype].material) as usize;
            let triangle = triangle - self.prototype_starts[prototype];
            return Some(Pick { picked: Picked::Instance { instance, triangle }, material: Some(material), distance: hit.t });
        }
        let material = self.triangle_materials[triangle] as usize;
        let mesh = self.mesh_starts.partition_point(|&start| start <= triangle);
        let picked = if material >= self.scene_materials {
            let quad = (triangle - scene.triangle_count()) / 2;
            Picked::QuadLight { light: self.quad_lights[quad] }
        } else {
            Picked::Mesh { mesh: mesh - 1, triangle: triangle - self.mesh_starts[mesh - 1] }
        };
        let material = (material < self.scene_materials).then_some(material);
        Some(Pick { picked, material, distance: hit.t })
    }
}

/// The camera ray (origin, unit direction) through `pixel`, as `shaders/integrator/camera.wgsl`
/// makes it without a lens: from the eye for a perspective camera, along the view from the
/// film rectangle for an orthographic one ([`Camera::ray`]).
pub fn camera_ray(camera: &Camera, (width, height): (u32, u32), (x, y): (f32, f32)) -> (Vec3, Vec3) {
    let ndc = (2.0 * x / width as f32 - 1.0, 1.0 - 2.0 * y / height as f32);
    camera.ray((width, height), ndc)
}

/// A short description of a pick for the inspector.
pub fn describe(scene: &Scene, pick: &Pick) -> String {
    let object = match &pick.picked {
        Picked::Mesh { mesh, triangle } => format!("mesh '{}' (#{mesh}), triangle {triangle}", scene.meshes[*mesh].name),
        Picked::Shape { shape } => format!("{:?} shape #{shape}", scene.shapes[*shape].kind),
        Picked::QuadLight { light } => format!("quad light #{light}"),
        Picked::Instance { instance, triangle } => {
            let placed = &scene.instances[*instance];
            format!("instance '{}' (#{instance}) of mesh '{}', triangle {triangle}", placed.name, scene.prototypes[placed.prototype as usize].name)
        }
    };
    format!("{object} at distance {:.4}", pick.distance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustic_scene::{Shape, cornell_box};
    use glam::Mat4;

    fn material_name(scene: &Scene, pick: Option<Pick>) -> String {
        let pick = pick.expect("a hit");
        scene.materials[pick.material.expect("a material")].name.clone()
    }

    #[test]
    fn the_cornell_walls_are_picked_with_their_materials() {
        let scene = cornell_box();
        let picker = Picker::new(&scene);
        let (w, h) = scene.resolution;
        let (w, h) = (w as f32, h as f32);
        let pick = |x: f32, y: f32| picker.pick(&scene, &scene.camera, scene.resolution, (x, y));
        assert_eq!(material_name(&scene, pick(0.03 * w, 0.5 * h)), "red");
        assert_eq!(material_name(&scene, pick(0.97 * w, 0.5 * h)), "green");
        assert_eq!(material_name(&scene, pick(0.3 * w, 0.08 * h)), "white", "the ceiling");
        let light = pick(0.5 * w, 0.14 * h);
        println!("{}", describe(&scene, light.as_ref().unwrap()));
        assert_eq!(material_name(&scene, light), "light");
        assert_eq!(pick(0.5 * w, 0.005 * h), None, "above the box's opening");
        let wall = pick(0.03 * w, 0.5 * h).unwrap();
        match wall.picked {
            Picked::Mesh { mesh, .. } => assert_eq!(scene.meshes[mesh].name, "left_wall_red"),
            other => panic!("expected the red wall mesh, got {other:?}"),
        }
    }

    /// An orthographic camera's rays run parallel from the film rectangle: a sphere of radius
    /// 0.5 at the view's centre is picked at the image centre and at 0.4 units off it (a
    /// perspective ray from the eye would miss there at this width), not at 0.6.
    #[test]
    fn an_orthographic_camera_picks_along_parallel_rays() {
        let mut scene = Scene::default();
        scene.materials.push(caustic_scene::Material::diffuse("ball", Vec3::ONE));
        scene.shapes.push(Shape::sphere(Mat4::IDENTITY, Vec3::ZERO, 0.5, 0));
        scene.camera.projection = caustic_scene::Projection::Orthographic { half_height: 1.0 };
        scene.resolution = (200, 200);
        let picker = Picker::new(&scene);
        // 100 pixels = 1 unit: pixel 100 + 100 u is u units right of the centre.
        let pick = |u: f32| picker.pick(&scene, &scene.camera, scene.resolution, (100.0 + 100.0 * u, 100.0));
        let centre = pick(0.0).expect("the sphere at the centre");
        assert!((centre.distance - 4.5).abs() < 1e-4, "the eye is 5 units away: {}", centre.distance);
        assert!(pick(0.4).is_some_and(|p| p.picked == Picked::Shape { shape: 0 }));
        assert_eq!(pick(0.6), None);
    }

    /// Two instances of one triangle, the second in another material: each is picked as its
    /// instance, wearing its material, where it stands.
    #[test]
    fn instances_are_picked_where_they_stand() {
        let mut scene = Scene::default();
        scene.materials.push(caustic_scene::Material::diffuse("own", Vec3::ONE));
        scene.materials.push(caustic_scene::Material::diffuse("worn", Vec3::ONE));
        let corners = vec![Vec3::new(-0.4, -0.4, 0.0), Vec3::new(0.4, -0.4, 0.0), Vec3::new(0.0, 0.4, 0.0)];
        scene.prototypes.push(caustic_scene::Mesh { name: "tri".into(), positions: corners, indices: vec![[0, 1, 2]], ..Default::default() });
        for (i, (x, material)) in [(-1.0, None), (1.0, Some(1))].into_iter().enumerate() {
            let object_to_world = Mat4::from_translation(Vec3::new(x, 0.0, 0.0));
            scene.instances.push(caustic_scene::Instance { name: format!("copy {i}"), prototype: 0, object_to_world, motion: None, material });
        }
        scene.camera.projection = caustic_scene::Projection::Orthographic { half_height: 2.0 };
        scene.resolution = (200, 200);
        let picker = Picker::new(&scene);
        // 50 pixels = 1 unit: pixel 100 + 50 u is u units right of the centre.
        let pick = |u: f32| picker.pick(&scene, &scene.camera, scene.resolution, (100.0 + 50.0 * u, 100.0));
        let (left, right) = (pick(-1.0).expect("the left copy"), pick(1.0).expect("the right copy"));
        println!("{} / {}", describe(&scene, &left), describe(&scene, &right));
        assert_eq!((left.picked, left.material), (Picked::Instance { instance: 0, triangle: 0 }, Some(0)));
        assert_eq!((right.picked, right.material), (Picked::Instance { instance: 1, triangle: 0 }, Some(1)));
        assert_eq!(pick(0.0), None, "between the copies");
    }

    #[test]
    fn shapes_quad_lights_and_the_sky_are_told_apart() {
        let mut scene = Scene::default();
        scene.materials.push(caustic_scene::Material::diffuse("ball", Vec3::ONE));
        scene.shapes.push(Shape::sphere(Mat4::IDENTITY, Vec3::new(-1.0, 0.0, 0.0), 0.5, 0));
        let quad = Light::Quad { corner: Vec3::new(0.5, -0.5, 0.0), edge_a: Vec3::X, edge_b: Vec3::Y, radiance: [Vec3::ONE; 4] };
        scene.lights.push(Light::Point { position: Vec3::Y, color: Vec3::ONE, attenuation: Default::default(), spread: 0.0 });
        scene.lights.push(quad);
        let picker = Picker::new(&scene);
        let (w, h) = (scene.resolution.0 as f32, scene.resolution.1 as f32);
        let at = |world: Vec3| {
            let (right, up, forward) = scene.camera.frame();
            let d = world - scene.camera.eye;
            let tan = (scene.camera.fov_y * 0.5).tan();
            let (x, y) = (d.dot(right) / d.dot(forward) / tan, d.dot(up) / d.dot(forward) / tan);
            picker.pick(&scene, &scene.camera, scene.resolution, ((x + 1.0) * 0.5 * w, (1.0 - y) * 0.5 * h))
        };
        let ball = at(Vec3::new(-1.0, 0.0, 0.0)).expect("the sphere");
        assert_eq!(ball.picked, Picked::Shape { shape: 0 });
        assert_eq!(ball.material, Some(0));
        assert!((ball.distance - 4.5).abs() < 0.1, "{}", ball.distance);
        let light = at(Vec3::new(1.0, 0.0, 0.0)).expect("the quad light");
        assert_eq!(light.picked, Picked::QuadLight { light: 1 });
        assert_eq!(light.material, None);
        assert_eq!(at(Vec3::new(0.0, 1.5, 0.0)), None, "the sky");
    }
}
