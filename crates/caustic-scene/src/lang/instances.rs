//! Instancing: `object NAME` ... `endObject` gathers the triangles between them into
//! prototype meshes ([`crate::Scene::prototypes`]), kept once; `instance NAME` places them
//! under the current transform (and motion), as often as the scene says. `instance FILE`
//! places an OBJ or PLY file's meshes, loaded once, wearing the current material.
//!
//! Objects may use other objects (those are copied in: one level of instancing reaches the
//! renderer); an object that uses itself, directly or through others, is a cycle and an error.
//! An instance whose material emits light is copied into the world too, so that the lights'
//! list samples it.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use super::state::Site;
use crate::{Instance, Mesh};
use glam::{DMat4, DVec3, Mat4};
use std::path::PathBuf;

/// An `object` whose `endObject` has not come yet.
#[derive(Clone, Debug)]
pub(super) struct OpenObject {
    /// The object's name.
    pub(super) name: String,
    /// `scene.meshes.len()` at `object`: the meshes from here on are the object's.
    pub(super) first_mesh: usize,
    /// Where `object` was written, for the end-of-input warning.
    pub(super) site: Site,
}

/// Commands that make analytic shapes, which an object cannot hold (nor lights:
/// [`super::lights::MAKES_LIGHT`]).
const NOT_IN_OBJECTS: &[&str] = &["sphere", "box", "plane", "disk"];

impl Interpreter {
    /// Executes `object`, `endObject` and `instance`; returns whether `a` is one of them.
    /// Inside an object, refuses the commands that make lights or shapes.
    pub(super) fn instance_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        match a.name {
            "object" => self.begin_object(a, at)?,
            "endObject" => self.end_object(a)?,
            "instance" => self.instance(a, at)?,
            name if NOT_IN_OBJECTS.contains(&name) || super::lights::MAKES_LIGHT.contains(&name) => {
                if let Some(open) = self.world.defining.last() {
                    return a.fail(format!("object '{}' can hold only triangles: put '{name}' outside object ... endObject", open.name));
                }
                return Ok(false);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    fn begin_object(&mut self, a: &Args, at: Location<'_>) -> Res<()> {
        a.expect(&[1])?;
        let name = a.text(0)?.to_string();
        if self.world.objects.contains_key(&name) {
            return a.fail_at(0, format!("object '{name}' is already defined"));
        }
        if self.world.defining.iter().any(|o| o.name == name) {
            return a.fail_at(0, format!("object '{name}' is already being defined (an object cannot contain itself)"));
        }
        let w = &mut self.world;
        w.open = None;
        let site = Site { file: at.file.to_path_buf(), line: at.line, column: a.name_column(), warned: false };
        w.defining.push(OpenObject { name, first_mesh: w.scene.meshes.len(), site });
        Ok(())
    }

    fn end_object(&mut self, a: &Args) -> Res<()> {
        a.expect(&[0])?;
        let Some(open) = self.world.defining.last() else {
            return a.fail("endObject without a matching object");
        };
        if let Some(moving) = self.world.scene.meshes[open.first_mesh..].iter().find(|m| m.motion.is_some()) {
            let message = format!("object '{}': the triangles of {} move; set `motion` before `instance` instead (an object is still)", open.name, moving.name);
            return a.fail(message);
        }
        let w = &mut self.world;
        let Some(open) = w.defining.pop() else { return a.fail("endObject without a matching object") };
        w.open = None;
        let meshes = w.scene.meshes.split_off(open.first_mesh);
        let first = w.scene.prototypes.len() as u32;
        let count = meshes.len() as u32;
        w.scene.prototypes.extend(meshes.into_iter().map(|m| Mesh { name: format!("{} ({})", open.name, m.name), ..m }));
        w.objects.insert(open.name, (first..first + count).collect());
        Ok(())
    }

    fn instance(&mut self, a: &Args, at: Location<'_>) -> Res<()> {
        a.expect(&[1])?;
        let name = a.text(0)?.to_string();
        if let Some(open) = self.world.defining.iter().find(|o| o.name == name) {
            return a.fail_at(0, format!("object '{}' instances itself (an instance cycle)", open.name));
        }
        let (prototypes, wears_current) = match self.world.objects.get(&name) {
            Some(prototypes) => (prototypes.clone(), false),
            None if is_mesh_file(&name) => (self.mesh_file(a, at, &name)?, true),
            None => {
                return a.fail_at(0, format!("no object named '{name}' (define it with `object {name}` ... `endObject`, or name an .obj or .ply file)"));
            }
        };
        let material = wears_current.then(|| self.world.material_index());
        let w = &mut self.world;
        // Objects are stored relative to the scene's origin like all geometry; files are not.
        let origin = w.origin(w.current.transform_point3(DVec3::ZERO));
        let back = if wears_current { DMat4::IDENTITY } else { DMat4::from_translation(origin) };
        let object_to_world: Mat4 = (DMat4::from_translation(-origin) * w.current * back).as_mat4();
        let placed =
            format!("{name} at {}:{}", at.file.file_name().map_or_else(|| at.file.display().to_string(), |f| f.to_string_lossy().into_owned()), at.line);
        let template = Instance { name: placed, prototype: 0, object_to_world, motion: w.motion, material };
        if let Err(e) = template.validate(w.scene.instances.len(), usize::MAX, usize::MAX) {
            return a.fail(e);
        }
        for prototype in prototypes {
            let instance = Instance { prototype, ..template.clone() };
            let mesh = &w.scene.prototypes[prototype as usize];
            let emits = w.scene.materials.get(instance.material.unwrap_or(mesh.material) as usize).is_some_and(|m| m.is_emissive());
            if emits || !w.defining.is_empty() {
                if w.triangles + mesh.triangle_count() > super::interpreter::MAX_TRIANGLES {
                    return a.fail(format!("more than {} triangles", super::interpreter::MAX_TRIANGLES));
                }
                w.triangles += mesh.triangle_count();
                w.scene.meshes.push(instance.placed(mesh));
                w.open = None;
            } else {
                w.scene.instances.push(instance);
            }
        }
        Ok(())
    }

    /// The prototypes of an OBJ or PLY file, loaded on its first `instance` with the current
    /// material.
    fn mesh_file(&mut self, a: &Args, at: Location<'_>, name: &str) -> Res<Vec<u32>> {
        if !self.file_access {
            return a.fail_at(0, "reading files is disabled in this session");
        }
        let path: PathBuf = match self.input_path(at.file, name) {
            Ok(path) => path,
            Err(message) => return a.fail_at(0, message),
        };
        if let Some(known) = self.world.mesh_files.get(&path) {
            return Ok(known.clone());
        }
        let loaded = match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("ply") => crate::ply_loader::load(&path, self.input_limits()),
            _ => crate::obj_loader::load(&path, self.input_limits()),
        };
        let loaded = match loaded {
            Ok(scene) => scene,
            Err(e) => return a.fail_at(0, e),
        };
        let triangles: usize = loaded.meshes.iter().map(Mesh::triangle_count).sum();
        let w = &mut self.world;
        if w.triangles + triangles > super::interpreter::MAX_TRIANGLES {
            return a.fail(format!("more than {} triangles", super::interpreter::MAX_TRIANGLES));
        }
        w.triangles += triangles;
        let material = w.material_index();
        let first = w.scene.prototypes.len() as u32;
        let count = loaded.meshes.len() as u32;
        w.scene.prototypes.extend(loaded.meshes.into_iter().map(|m| Mesh { material, motion: None, ..m }));
        let prototypes: Vec<u32> = (first..first + count).collect();
        w.mesh_files.insert(path, prototypes.clone());
        Ok(prototypes)
    }

    /// End-of-input warnings for objects never closed (their triangles stay in the world).
    pub(super) fn unclosed_objects(&mut self) -> Vec<(Site, String)> {
        std::mem::take(&mut self.world.defining)
            .into_iter()
            .map(|o| {
                let message = format!("object '{}' has no endObject before the end of input: its triangles render in place", o.name);
                (o.site, message)
            })
            .collect()
    }
}

/// Whether `name` names an OBJ or PLY file (by its extension).
fn is_mesh_file(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".obj") || lower.ends_with(".ply")
}

#[cfg(test)]
mod tests {
    use crate::lang::parse_str;
    use glam::Vec3;
    use std::path::Path;

    fn parse(text: &str) -> Result<crate::Scene, String> {
        parse_str(text, Path::new("instances.scene")).map(|(s, _)| s).map_err(|e| e.to_string())
    }

    const TRIANGLE: &str = "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n";

    #[test]
    fn an_object_is_stored_once_and_placed_by_each_instance() {
        let text = format!("{TRIANGLE}object tri\ntri 0 1 2\nendObject\ninstance tri\ntranslate 5 0 0\ninstance tri\nscale 2 2 2\ninstance tri\n");
        let scene = parse(&text).unwrap();
        assert_eq!((scene.meshes.len(), scene.prototypes.len(), scene.instances.len()), (0, 1, 3));
        let placed: Vec<Vec3> = scene.instances.iter().map(|i| i.object_to_world.transform_point3(Vec3::X)).collect();
        assert_eq!(placed, [Vec3::X, Vec3::new(6.0, 0.0, 0.0), Vec3::new(7.0, 0.0, 0.0)]);
        assert!(scene.instances.iter().all(|i| i.material.is_none()));
        scene.validate().unwrap();
        // Flattened, the same triangles as written out by hand.
        let mut flat = scene.clone();
        crate::flatten_instances(&mut flat);
        assert_eq!(flat.meshes[2].positions[1], Vec3::new(7.0, 0.0, 0.0));
    }

    #[test]
    fn objects_nest_by_copy_and_cycles_are_errors() {
        let text = format!("{TRIANGLE}object a\ntri 0 1 2\nendObject\nobject b\ninstance a\ntranslate 0 0 1\ninstance a\nendObject\ninstance b\n");
        let scene = parse(&text).unwrap();
        // b holds two copies of a: two prototypes, each placed by b's instance (under the
        // `translate` still current: transforms are not scoped by objects).
        assert_eq!((scene.prototypes.len(), scene.instances.len()), (3, 2));
        assert_eq!(scene.instances.iter().map(|i| scene.prototypes[i.prototype as usize].triangle_count()).sum::<usize>(), 2);
        assert_eq!(scene.instances[1].object_to_world.transform_point3(scene.prototypes[2].positions[0]), glam::Vec3::new(0.0, 0.0, 2.0));

        let cycle = parse(&format!("{TRIANGLE}object a\ntri 0 1 2\ninstance a\nendObject\n")).unwrap_err();
        assert!(cycle.ends_with("instances.scene:6:10: instance: object 'a' instances itself (an instance cycle)"), "{cycle}");
        let missing = parse("instance tree\n").unwrap_err();
        assert!(missing.contains("1:10: instance: no object named 'tree'"), "{missing}");
        let twice = parse("object a\nendObject\nobject a\n").unwrap_err();
        assert!(twice.contains("3:8: object: object 'a' is already defined"), "{twice}");
        let unmatched = parse("endObject\n").unwrap_err();
        assert!(unmatched.contains("1:1: endObject: endObject without a matching object"), "{unmatched}");
        let shape = parse("object a\nsphere 0 0 0 1\n").unwrap_err();
        assert!(shape.contains("2:1: sphere: object 'a' can hold only triangles"), "{shape}");
        for light in ["point 0 1 0 1 1 1", "tubeLight 0 1 0  1 1 0  0.1  1 1 1", "sphereLight 0 1 0 0.5 1 1 1"] {
            let error = parse(&format!("object a\n{light}\n")).unwrap_err();
            assert!(error.contains("object 'a' can hold only triangles"), "{light}: {error}");
        }
    }

    #[test]
    fn singular_transforms_moving_objects_and_files_without_access_are_errors() {
        let text = format!("{TRIANGLE}object a\ntri 0 1 2\nendObject\nscale 0 1 1\ninstance a\n");
        let singular = parse(&text).unwrap_err();
        assert!(
            singular.ends_with("8:1: instance: instance 'a at instances.scene:8' (#0): transform is singular (a zero scale flattens the mesh)"),
            "{singular}"
        );
        let moving = parse(&format!("{TRIANGLE}object a\nmotion 1 0 0\ntri 0 1 2\nendObject\n")).unwrap_err();
        assert!(moving.contains("7:1: endObject: object 'a': the triangles of") && moving.contains("move"), "{moving}");
        let file = parse("instance bunny.ply\n").unwrap_err();
        assert!(file.contains("1:10: instance: reading files is disabled"), "{file}");
    }

    #[test]
    fn instances_move_and_emitters_are_copied_into_the_world() {
        let text = format!("{TRIANGLE}object a\ntri 0 1 2\nendObject\nshutter 0 1\nmotion 2 0 0\ninstance a\n");
        let scene = parse(&text).unwrap();
        let instance = &scene.instances[0];
        assert!(instance.motion.is_some());
        let text = format!("{TRIANGLE}material flat\nemission 1 1 1\nobject lamp\ntri 0 1 2\nendObject\ninstance lamp\n");
        let scene = parse(&text).unwrap();
        assert_eq!((scene.meshes.len(), scene.instances.len()), (1, 0));
        assert_eq!(scene.emissive_triangles().len(), 1);
    }

    #[test]
    fn an_unclosed_object_is_a_warning_and_renders_in_place() {
        let (scene, warnings) = parse_str(&format!("{TRIANGLE}object a\ntri 0 1 2\n"), Path::new("open.scene")).unwrap();
        assert_eq!((scene.meshes.len(), scene.prototypes.len()), (1, 0));
        assert!(warnings.iter().any(|w| w.message.contains("object 'a' has no endObject")), "{warnings:?}");
    }
}
