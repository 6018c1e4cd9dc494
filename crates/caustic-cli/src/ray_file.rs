//! Ray files shared with other tracers: little-endian f32 records `ox oy oz dx dy dz`, and the
//! hit files `caustic bench --hits` writes for them (n f32 distances, then n i32 triangle
//! indices, -1 on a miss), so that results can be compared ray by ray.

use anyhow::{Context, bail};
use caustic_gpu::{ExternalRay, TracedRay};
use glam::Vec3;
use std::path::Path;

/// Bytes of one ray record.
pub const RAY_RECORD_BYTES: usize = 24;

/// Reads a ray file. Errors name the file and, for a bad record, its index: a length that is
/// not a whole number of records, a non-finite value, or a zero direction.
pub fn read_rays(path: &Path) -> anyhow::Result<Vec<ExternalRay>> {
    let bytes = caustic_scene::InputLimits::default().read(path).context("cannot read the ray file")?;
    parse_rays(&bytes).with_context(|| format!("ray file {}", path.display()))
}

/// Parses ray records from bytes (see [`read_rays`]).
pub fn parse_rays(bytes: &[u8]) -> anyhow::Result<Vec<ExternalRay>> {
    if bytes.is_empty() || !bytes.len().is_multiple_of(RAY_RECORD_BYTES) {
        bail!("{} bytes is not a whole, non-zero number of {RAY_RECORD_BYTES}-byte ray records", bytes.len());
    }
    bytes
        .chunks_exact(RAY_RECORD_BYTES)
        .enumerate()
        .map(|(index, record)| {
            let v: [f32; 6] = std::array::from_fn(|i| f32::from_le_bytes([record[4 * i], record[4 * i + 1], record[4 * i + 2], record[4 * i + 3]]));
            let ray = ExternalRay { origin: Vec3::new(v[0], v[1], v[2]), direction: Vec3::new(v[3], v[4], v[5]) };
            if !v.iter().all(|x| x.is_finite()) {
                bail!("ray {index}: non-finite value in {v:?}");
            }
            if ray.direction == Vec3::ZERO {
                bail!("ray {index}: zero direction");
            }
            Ok(ray)
        })
        .collect()
}

/// The hit file's bytes for traced rays: distances (inf on a miss), then triangle indices
/// (-1 on a miss), little-endian.
pub fn encode_hits(traced: &[TracedRay]) -> Vec<u8> {
    let distances = traced.iter().map(|r| if r.triangle.is_some() { r.t } else { f32::INFINITY }.to_le_bytes());
    let indices = traced.iter().map(|r| r.triangle.map_or(-1, |t| t as i32).to_le_bytes());
    distances.chain(indices).flatten().collect()
}

/// Writes the hit file atomically, so an interrupted run leaves no half-written file.
pub fn write_hits(path: &Path, traced: &[TracedRay]) -> anyhow::Result<()> {
    caustic_image::write_file_atomically(path, &encode_hits(traced)).with_context(|| format!("cannot write hit file {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(values: [f32; 6]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    #[test]
    fn parses_records_in_order() {
        let bytes = [record([1.0, 2.0, 3.0, 0.0, 0.0, -1.0]), record([0.0, 0.0, 0.0, 2.0, 0.0, 0.0])].concat();
        let rays = parse_rays(&bytes).unwrap();
        assert_eq!(rays.len(), 2);
        assert_eq!(rays[0].origin, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(rays[1].direction, Vec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn rejects_partial_records_non_finite_values_and_zero_directions() {
        let good = record([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        let partial = parse_rays(&good[..20]).unwrap_err().to_string();
        assert!(partial.contains("20 bytes"), "{partial}");
        let nan = [good.clone(), record([0.0, f32::NAN, 0.0, 0.0, 0.0, 1.0])].concat();
        assert!(parse_rays(&nan).unwrap_err().to_string().contains("ray 1: non-finite"));
        let zero = record([0.0; 6]);
        assert!(parse_rays(&zero).unwrap_err().to_string().contains("ray 0: zero direction"));
        assert!(parse_rays(&[]).is_err());
    }

    #[test]
    fn hits_are_distances_then_indices() {
        let ray = |t, triangle| TracedRay { origin: Vec3::ZERO, direction: Vec3::Z, t, triangle };
        let bytes = encode_hits(&[ray(2.5, Some(7)), ray(3.0e38, None)]);
        assert_eq!(bytes.len(), 16);
        assert_eq!(f32::from_le_bytes(bytes[0..4].try_into().unwrap()), 2.5);
        assert_eq!(f32::from_le_bytes(bytes[4..8].try_into().unwrap()), f32::INFINITY);
        assert_eq!(i32::from_le_bytes(bytes[8..12].try_into().unwrap()), 7);
        assert_eq!(i32::from_le_bytes(bytes[12..16].try_into().unwrap()), -1);
    }
}
