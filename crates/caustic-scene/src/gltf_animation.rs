//! glTF animation for motion blur: the translation and rotation channels of a file's first
//! animation, sampled at the shutter's open and close times (seconds of the animation) as
//! glTF interpolates them (`STEP`, `LINEAR` with slerp for rotations, `CUBICSPLINE` Hermite
//! splines); before the first key a channel holds its first value, after the last its last.
//! Scale and morph-weight channels are ignored with a warning: motion blur moves objects
//! rigidly.

use crate::SceneError;
use crate::mesh_scene::warn;
use glam::{Mat4, Quat, Vec3};
use gltf::animation::Interpolation;
use gltf::animation::util::ReadOutputs;
use std::collections::HashMap;
use std::path::Path;

/// Key times and values of one channel.
struct Track<T> {
    times: Vec<f32>,
    /// One value per key; `CUBICSPLINE` stores (in-tangent, value, out-tangent) per key.
    values: Vec<T>,
    interpolation: Interpolation,
}

/// What a channel's values can be blended as.
trait Keyed: Copy {
    fn scaled_add(self, other: Self, weight: f32) -> Self;
    fn interpolate(self, other: Self, u: f32) -> Self;
    fn normalized(self) -> Self;
}

impl Keyed for Vec3 {
    fn scaled_add(self, other: Vec3, weight: f32) -> Vec3 {
        self + other * weight
    }
    fn interpolate(self, other: Vec3, u: f32) -> Vec3 {
        self.lerp(other, u)
    }
    fn normalized(self) -> Vec3 {
        self
    }
}

impl Keyed for Quat {
    fn scaled_add(self, other: Quat, weight: f32) -> Quat {
        self + other * weight
    }
    fn interpolate(self, other: Quat, u: f32) -> Quat {
        self.slerp(other, u)
    }
    fn normalized(self) -> Quat {
        self.normalize()
    }
}

impl<T: Keyed> Track<T> {
    /// The channel's value at `time`.
    fn sample(&self, time: f32) -> T {
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| if cubic { self.values[3 * k + 1] } else { self.values[k] };
        let last = self.times.len() - 1;
        let k = self.times.partition_point(|&t| t <= time);
        if k == 0 {
            return value(0);
        }
        if k > last {
            return value(last);
        }
        let (k, dt) = (k - 1, self.times[k] - self.times[k - 1]);
        let u = (time - self.times[k]) / dt;
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear => value(k).interpolate(value(k + 1), u),
            Interpolation::CubicSpline => {
                let (u2, u3) = (u * u, u * u * u);
                let out_tangent = self.values[3 * k + 2];
                let in_tangent = self.values[3 * (k + 1)];
                value(k)
                    .scaled_add(value(k), 2.0 * u3 - 3.0 * u2)
                    .scaled_add(out_tangent, dt * (u3 - 2.0 * u2 + u))
                    .scaled_add(value(k + 1), 3.0 * u2 - 2.0 * u3)
                    .scaled_add(in_tangent, dt * (u3 - u2))
                    .normalized()
            }
        }
    }
}

/// The animated channels of one node.
#[derive(Default)]
struct NodeTracks {
    translation: Option<Track<Vec3>>,
    rotation: Option<Track<Quat>>,
}

/// The first animation's translation and rotation channels, by node index.
pub(crate) struct Animation {
    nodes: HashMap<usize, NodeTracks>,
}

impl Animation {
    /// Reads the document's first animation, or `None` when it has none. Malformed channels
    /// (times not increasing or not finite, too few values) are errors naming the channel.
    pub(crate) fn read(path: &Path, document: &gltf::Document, buffers: &[gltf::buffer::Data]) -> Result<Option<Animation>, SceneError> {
        let Some(animation) = document.animations().next() else {
            return Ok(None);
        };
        let mut nodes: HashMap<usize, NodeTracks> = HashMap::new();
        for (index, channel) in animation.channels().enumerate() {
            let fail = |what: &str| SceneError::file(path, format!("animation 0, channel {index}: {what}"));
            let reader = channel.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let times: Vec<f32> = reader.read_inputs().ok_or_else(|| fail("cannot read the key times"))?.collect();
            if times.is_empty() || times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] <= w[0]) {
                return Err(fail("key times must be finite and strictly increasing"));
            }
            let interpolation = channel.sampler().interpolation();
            let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
            let tracks = nodes.entry(channel.target().node().index()).or_default();
            match reader.read_outputs().ok_or_else(|| fail("cannot read the values"))? {
                ReadOutputs::Translations(values) => {
                    let values: Vec<Vec3> = values.map(Vec3::from).collect();
                    check_values(values.len(), times.len() * per_key, values.iter().all(|v| v.is_finite())).map_err(|m| fail(&m))?;
                    tracks.translation = Some(Track { times, values, interpolation });
                }
                ReadOutputs::Rotations(values) => {
                    let values: Vec<Quat> = values.into_f32().map(Quat::from_array).collect();
                    check_values(values.len(), times.len() * per_key, values.iter().all(|q| q.is_finite())).map_err(|m| fail(&m))?;
                    tracks.rotation = Some(Track { times, values, interpolation });
                }
                ReadOutputs::Scales(_) | ReadOutputs::MorphTargetWeights(_) => {
                    warn(path, &format!("animation 0, channel {index}: scale and morph-weight channels are ignored (motion blur is rigid)"));
                }
            }
        }
        Ok(Some(Animation { nodes }))
    }

    /// The node's local transform at `time`: its translation and rotation from the animated
    /// channels (else its own), its own scale.
    pub(crate) fn local(&self, node: &gltf::Node, time: f32) -> Mat4 {
        let (translation, rotation, scale) = node.transform().decomposed();
        let Some(tracks) = self.nodes.get(&node.index()) else {
            return Mat4::from_cols_array_2d(&node.transform().matrix());
        };
        let translation = tracks.translation.as_ref().map_or(Vec3::from(translation), |t| t.sample(time));
        let rotation = tracks.rotation.as_ref().map_or(Quat::from_array(rotation), |t| t.sample(time).normalize());
        Mat4::from_scale_rotation_translation(Vec3::from(scale), rotation, translation)
    }
}

/// `Ok` when a channel has `count` finite values and needs `needed`.
fn check_values(count: usize, needed: usize, finite: bool) -> Result<(), String> {
    if count != needed {
        return Err(format!("{count} values for {needed} needed"));
    }
    if !finite {
        return Err("a value is not finite".to_string());
    }
    Ok(())
}
