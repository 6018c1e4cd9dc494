//! The pixel inspector: what one path of one pixel did, bounce by bounce.
//!
//! [`crate::PathTracer::inspect`] re-runs a sample of one pixel with the kernel's inspector
//! hooks armed (`shaders/integrator/inspect.wgsl`): the same kernel and random numbers as a
//! render, writing each ray, hit, BSDF sample, light sample and the path's throughput into a
//! debug buffer ([`InspectRecord`]). This module decodes that buffer into a [`PathRecord`].
//! Bidirectional path tracing's record holds its camera subpath as the bounces and every
//! connection strategy (s, t) its sample tried ([`ConnectionRecord`]).

use crate::GpuError;
use crate::gpu_types::{INSPECT_MAX_BOUNCES, INSPECT_MAX_CONNECTIONS, InspectBounce, InspectConnection, InspectRecord, NO_PIXEL};
use caustic_scene::Units;
use glam::Vec3;

const SHAPE_BIT: u32 = 0x8000_0000;
const NONE: u32 = u32::MAX;
// InspectBounce::flags, as in inspect.wgsl.
const SURFACE: u32 = 1;
const FRONT_FACE: u32 = 2;
const BSDF_SAMPLED: u32 = 4;
const LIGHT_SAMPLED: u32 = 8;
const LIGHT_DELTA: u32 = 16;
const LIGHT_OCCLUDED: u32 = 32;
// InspectConnection::flags, as in inspect.wgsl.
const LINK_OCCLUDED: u32 = 1;
const LINK_LIGHT_DIRECTION: u32 = 2;

/// One inspected path: the pixel's sample, its rays in order, and why it ended.
#[derive(Clone, Debug, PartialEq)]
pub struct PathRecord {
    /// The pixel (x, y).
    pub pixel: (u32, u32),
    /// The global sample index of the path.
    pub sample: u32,
    /// The rays of the path in order: the camera ray first. At most [`INSPECT_MAX_BOUNCES`]
    /// are kept; `ray_count` says how many there were.
    pub bounces: Vec<BounceRecord>,
    /// Rays the path traced (more than `bounces.len()` if the path was longer than the record).
    pub ray_count: u32,
    /// Why the path ended.
    pub termination: Termination,
    /// The sample's radiance estimate: what the pixel's film receives (for bidirectional
    /// path tracing, without its light subpath's t = 1 splats, which land on other pixels).
    pub radiance: Vec3,
    /// Bidirectional path tracing's connection strategies in the order the sample tried them
    /// (the first [`INSPECT_MAX_CONNECTIONS`]); empty for the other integrators.
    pub connections: Vec<ConnectionRecord>,
    /// Strategies the sample tried (more than `connections.len()` if the record was full).
    pub connection_count: u32,
}

/// One connection strategy of a bidirectional sample: `s` light subpath vertices joined to
/// `t` camera subpath vertices (Veach's notation: s = 0 the camera subpath found an emitter,
/// s = 1 a light sampled from the camera vertex, t = 1 a light vertex seen by the camera and
/// splatted to the pixel it lands on). Strategies that found nothing to join (s = 0 at a
/// surface that does not emit) are not recorded.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectionRecord {
    /// Light subpath vertices.
    pub s: u32,
    /// Camera subpath vertices, the lens point counted.
    pub t: u32,
    /// The pixel the contribution lands on: the inspected one for t >= 2, the one the light
    /// vertex is seen in for t = 1; `None` where the camera does not see it.
    pub pixel: Option<(u32, u32)>,
    /// The camera subpath's end: its last surface vertex (for s = 0 the vertex before the
    /// emitter), or the lens point for t = 1.
    pub camera_point: Vec3,
    /// The light subpath's end.
    pub light_end: LinkEnd,
    /// Whether the shadow ray between the ends was blocked.
    pub occluded: bool,
    /// The contribution before the MIS weight (0 where blocked or nothing scatters along the
    /// connection).
    pub contribution: Vec3,
    /// The power-heuristic weight of the strategy for this path (0 where not reached).
    pub mis_weight: f32,
}

/// Where a connection's light side ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkEnd {
    /// A point: a light subpath vertex, a point sampled on a light, or the emitter a camera
    /// ray hit.
    Point(Vec3),
    /// A light at infinity (directional, environment), by the unit direction towards it.
    Direction(Vec3),
}

impl ConnectionRecord {
    /// The weighted contribution: what the strategy adds to its pixel's sample.
    pub fn weighted(&self) -> Vec3 {
        self.contribution * self.mis_weight
    }

    fn decode(c: &InspectConnection, width: u32, units: &Units) -> ConnectionRecord {
        let light = Vec3::from(c.light_point);
        ConnectionRecord {
            s: c.s,
            t: c.t,
            pixel: (c.pixel != NO_PIXEL).then(|| (c.pixel % width, c.pixel / width)),
            camera_point: units.world_point(Vec3::from(c.camera_point)),
            light_end: if c.flags & LINK_LIGHT_DIRECTION != 0 { LinkEnd::Direction(light) } else { LinkEnd::Point(units.world_point(light)) },
            occluded: c.flags & LINK_OCCLUDED != 0,
            contribution: Vec3::from(c.contribution),
            mis_weight: c.mis_weight,
        }
    }
}

/// Why a path ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The last ray hit nothing (it gathered the environment).
    Escaped,
    /// The path reached the maximum number of bounces.
    MaxDepth,
    /// Russian roulette ended it.
    RussianRoulette,
    /// The BSDF sample had no density or pointed into the surface.
    Absorbed,
}

impl Termination {
    /// A short name, as `caustic debug-pixel` prints it.
    pub fn name(self) -> &'static str {
        match self {
            Termination::Escaped => "escaped",
            Termination::MaxDepth => "max-depth",
            Termination::RussianRoulette => "roulette",
            Termination::Absorbed => "absorbed",
        }
    }
}

/// A primitive a ray hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Primitive {
    /// A scene triangle, by index into the scene's triangles.
    Triangle(u32),
    /// An analytic shape, by index into the scene's shapes.
    Shape(u32),
}

/// One ray of a path and what happened where it landed.
#[derive(Clone, Debug, PartialEq)]
pub struct BounceRecord {
    /// Ray origin (offset off the previous surface).
    pub origin: Vec3,
    /// Unit ray direction.
    pub direction: Vec3,
    /// The surface the ray hit; `None` if it escaped.
    pub hit: Option<SurfaceRecord>,
    /// Next-event estimation at the hit, if it ran.
    pub light: Option<LightRecord>,
    /// The BSDF sample that continues the path, if one was drawn.
    pub bsdf: Option<BsdfRecord>,
    /// The path throughput arriving along this ray.
    pub throughput: Vec3,
    /// Radiance the path had gathered before this ray.
    pub radiance: Vec3,
}

/// A ray's closest hit.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceRecord {
    /// Distance along the ray.
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// The primitive hit.
    pub primitive: Primitive,
    /// Whether the ray hit the front (counter-clockwise) face.
    pub front_face: bool,
    /// Shading normal, on the side the ray came from.
    pub shading_normal: Vec3,
    /// Geometric normal, on the side the ray came from.
    pub geometric_normal: Vec3,
    /// Material index.
    pub material: u32,
}

/// A BSDF sample.
#[derive(Clone, Debug, PartialEq)]
pub struct BsdfRecord {
    /// Sampled direction (world space).
    pub wi: Vec3,
    /// Its solid-angle density.
    pub pdf: f32,
    /// f cos / pdf: the factor the throughput is multiplied by.
    pub weight: Vec3,
}

/// A light sample of next-event estimation.
#[derive(Clone, Debug, PartialEq)]
pub struct LightRecord {
    /// Index of the light chosen, in the device's light list.
    pub light: u32,
    /// Direction to the sampled point.
    pub wi: Vec3,
    /// Density of the sample: solid angle (area lights, selection included) or the selection
    /// probability (delta lights).
    pub pdf: f32,
    /// Whether the light is a point or directional light.
    pub delta: bool,
    /// Whether the shadow ray was blocked.
    pub occluded: bool,
    /// MIS weight against BSDF sampling (0 if the sample was rejected before weighting).
    pub mis_weight: f32,
    /// f Li cos w / pdf, before the path throughput (0 if rejected or occluded).
    pub contribution: Vec3,
}

impl PathRecord {
    /// Decodes the kernel's record of an image `width` pixels wide, positions and distances
    /// converted from the device's `units` to the scene's coordinates (those of its camera
    /// and meshes; world coordinates less `Scene::origin`).
    pub fn decode(record: &InspectRecord, width: u32, units: &Units) -> Result<PathRecord, GpuError> {
        let termination = match record.termination {
            1 => Termination::Escaped,
            2 => Termination::MaxDepth,
            3 => Termination::RussianRoulette,
            4 => Termination::Absorbed,
            other => return Err(GpuError::Runtime(format!("the inspected path has no termination recorded (code {other})"))),
        };
        let kept = (record.bounce_count as usize).min(INSPECT_MAX_BOUNCES);
        let links = (record.connection_count as usize).min(INSPECT_MAX_CONNECTIONS);
        Ok(PathRecord {
            pixel: (record.pixel % width, record.pixel / width),
            sample: record.sample,
            bounces: record.bounces[..kept].iter().map(|b| BounceRecord::decode(b, units)).collect(),
            ray_count: record.bounce_count,
            termination,
            radiance: Vec3::from(record.radiance),
            connections: record.connections[..links].iter().map(|c| ConnectionRecord::decode(c, width, units)).collect(),
            connection_count: record.connection_count,
        })
    }
}

impl BounceRecord {
    fn decode(b: &InspectBounce, units: &Units) -> BounceRecord {
        let has = |flag: u32| b.flags & flag != 0;
        let hit = has(SURFACE).then(|| SurfaceRecord {
            t: units.world_length(b.t),
            point: units.world_point(Vec3::from(b.point)),
            primitive: if b.primitive & SHAPE_BIT != 0 { Primitive::Shape(b.primitive & !SHAPE_BIT) } else { Primitive::Triangle(b.primitive) },
            front_face: has(FRONT_FACE),
            shading_normal: Vec3::from(b.shading_normal),
            geometric_normal: Vec3::from(b.geometric_normal),
            material: b.material,
        });
        let light = (has(LIGHT_SAMPLED) && b.light_index != NONE).then(|| LightRecord {
            light: b.light_index,
            wi: Vec3::from(b.light_wi),
            pdf: b.light_pdf,
            delta: has(LIGHT_DELTA),
            occluded: has(LIGHT_OCCLUDED),
            mis_weight: b.light_mis_weight,
            contribution: Vec3::from(b.light_contribution),
        });
        let bsdf = has(BSDF_SAMPLED).then(|| BsdfRecord { wi: Vec3::from(b.bsdf_wi), pdf: b.bsdf_pdf, weight: Vec3::from(b.bsdf_weight) });
        BounceRecord {
            origin: units.world_point(Vec3::from(b.origin)),
            direction: Vec3::from(b.direction),
            hit,
            light,
            bsdf,
            throughput: Vec3::from(b.throughput),
            radiance: Vec3::from(b.radiance),
        }
    }
}
