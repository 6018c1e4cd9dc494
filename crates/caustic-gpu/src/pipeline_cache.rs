//! Compiled pipelines kept across runs, where the driver allows (a Vulkan `VkPipelineCache`
//! through wgpu's [`wgpu::PipelineCache`]).
//!
//! A render's first pipelines take seconds to compile. Many drivers keep their own cache
//! (Mesa's shader disk cache holds lavapipe's LLVM output), others leave it to the
//! application; the pipeline cache serves the second kind (the driver decides what it stores:
//! lavapipe stores nothing in it, its kernels live in Mesa's disk cache).
//!
//! The cache lives in one file per adapter ([`wgpu::util::pipeline_cache_key`]) in the folder
//! [`cache_folder`] names: `CAUSTIC_CACHE_DIR`, else `$XDG_CACHE_HOME/caustic`, else
//! `~/.cache/caustic`. `CAUSTIC_CACHE_DIR=off` (or empty) turns it off. A cache is only ever
//! a shortcut: a file that is missing, not a regular file, too large, damaged (each file
//! carries its length and a checksum) or from another driver is ignored (wgpu validates its
//! own header and falls back to an empty cache), and a failure to save it is the caller's to
//! report (`caustic render` warns; a dropped context ignores it). It is saved atomically
//! ([`caustic_image::write_file_atomically`]), so a run interrupted while saving leaves
//! the previous cache whole.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Largest cache file read back: a larger one is ignored (and replaced when saved).
pub const MAX_CACHE_BYTES: u64 = 512 << 20;

/// The environment variable that names the cache folder, or turns the cache off.
pub const CACHE_DIR_VARIABLE: &str = "CAUSTIC_CACHE_DIR";

/// A device's pipeline cache and the file it is loaded from and saved to.
pub struct PipelineCacheFile {
    cache: wgpu::PipelineCache,
    path: PathBuf,
    /// Checksum of the data last loaded or saved, so an unchanged cache is not written again
    /// (a change that keeps the length is still saved).
    saved: Mutex<Option<u64>>,
}

impl PipelineCacheFile {
    /// The cache of `device` (which must have been opened with
    /// [`wgpu::Features::PIPELINE_CACHE`]) for the adapter `info` describes, loaded from its
    /// file in `folder` if there is a usable one; `None` where the backend has no pipeline
    /// cache.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo, folder: &Path) -> Option<PipelineCacheFile> {
        if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
            return None;
        }
        let path = folder.join(wgpu::util::pipeline_cache_key(info)?);
        let data = read_cache(&path).and_then(|file| payload(&file).map(<[u8]>::to_vec));
        let cache = create(device, data.as_deref());
        let saved = Mutex::new(data.as_deref().map(checksum));
        Some(PipelineCacheFile { cache, path, saved })
    }

    /// The cache, for pipeline descriptors.
    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    /// The file the cache is saved to.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the cache to its file if its size changed since it was loaded or last saved,
    /// atomically (a temporary file beside it, renamed over it); the error names the file.
    pub fn save(&self) -> Result<(), String> {
        let Some(data) = self.cache.get_data() else { return Ok(()) };
        let sum = checksum(&data);
        let mut saved = self.saved.lock().unwrap_or_else(|e| e.into_inner());
        if *saved == Some(sum) {
            return Ok(());
        }
        let failed = |e: &dyn std::fmt::Display| format!("could not save the pipeline cache {}: {e}", self.path.display());
        if let Some(folder) = self.path.parent() {
            std::fs::create_dir_all(folder).map_err(|e| failed(&e))?;
        }
        caustic_image::write_file_atomically(&self.path, &framed(&data)).map_err(|e| failed(&e))?;
        *saved = Some(sum);
        Ok(())
    }
}

/// The driver's pipeline cache, seeded with `data`.
#[allow(unsafe_code)]
fn create(device: &wgpu::Device, data: Option<&[u8]>) -> wgpu::PipelineCache {
    // SAFETY: wgpu requires `data` to be bytes its `get_data` returned. They are: `payload`
    // passes on only a file this module framed with its magic, length and checksum when it
    // saved `get_data`'s bytes, so a truncated, corrupted or foreign file never reaches the
    // driver; wgpu then checks its own header (driver, device, version, length) and, with
    // `fallback`, starts an empty cache when it does not match.
    unsafe { device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor { label: Some("caustic pipelines"), data, fallback: true }) }
}

/// The first bytes of a cache file Caustic wrote.
const MAGIC: &[u8; 8] = b"CAUSTPC1";

/// `data` framed for its file: [`MAGIC`], its length and its FNV-1a checksum (little-endian
/// `u64`s), then the bytes.
fn framed(data: &[u8]) -> Vec<u8> {
    let mut file = Vec::with_capacity(data.len() + 24);
    file.extend_from_slice(MAGIC);
    file.extend_from_slice(&(data.len() as u64).to_le_bytes());
    file.extend_from_slice(&checksum(data).to_le_bytes());
    file.extend_from_slice(data);
    file
}

/// The bytes a [`framed`] file holds, if its magic, length and checksum are right.
fn payload(file: &[u8]) -> Option<&[u8]> {
    let (header, data) = file.split_at_checked(24)?;
    let word = |i: usize| u64::from_le_bytes(header[i..i + 8].try_into().expect("eight bytes"));
    (header[..8] == MAGIC[..] && word(8) == data.len() as u64 && word(16) == checksum(data)).then_some(data)
}

/// 64-bit FNV-1a: enough to catch a damaged file (it is not a defence against a crafted one,
/// which needs write access to the user's own cache folder).
fn checksum(data: &[u8]) -> u64 {
    data.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &byte| (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3))
}

/// The folder pipeline caches live in: `CAUSTIC_CACHE_DIR` if set (`off` or empty: none),
/// else `$XDG_CACHE_HOME/caustic`, else `$HOME/.cache/caustic`; `None` when caching is off
/// or no folder can be named.
pub fn cache_folder() -> Option<PathBuf> {
    folder_from(std::env::var_os(CACHE_DIR_VARIABLE), std::env::var_os("XDG_CACHE_HOME"), std::env::var_os("HOME"))
}

fn folder_from(explicit: Option<std::ffi::OsString>, xdg: Option<std::ffi::OsString>, home: Option<std::ffi::OsString>) -> Option<PathBuf> {
    let non_empty = |v: Option<std::ffi::OsString>| v.filter(|v| !v.is_empty());
    if let Some(explicit) = explicit {
        return (!explicit.is_empty() && explicit != "off").then(|| PathBuf::from(explicit));
    }
    non_empty(xdg).map(|x| PathBuf::from(x).join("caustic")).or_else(|| non_empty(home).map(|h| PathBuf::from(h).join(".cache").join("caustic")))
}

/// The cache file's bytes, if it is a regular file within [`MAX_CACHE_BYTES`] that can be read.
fn read_cache(path: &Path) -> Option<Vec<u8>> {
    let metadata = std::fs::metadata(path).ok()?;
    if !metadata.is_file() || metadata.len() > MAX_CACHE_BYTES {
        return None;
    }
    let data = std::fs::read(path).ok()?;
    (data.len() as u64 <= MAX_CACHE_BYTES).then_some(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_follows_the_variable_then_xdg_then_home() {
        let os = |s: &str| Some(std::ffi::OsString::from(s));
        assert_eq!(folder_from(os("/c"), os("/x"), os("/h")), Some(PathBuf::from("/c")));
        assert_eq!(folder_from(os("off"), os("/x"), os("/h")), None);
        assert_eq!(folder_from(os(""), os("/x"), os("/h")), None);
        assert_eq!(folder_from(None, os("/x"), os("/h")), Some(PathBuf::from("/x/caustic")));
        assert_eq!(folder_from(None, os(""), os("/h")), Some(PathBuf::from("/h/.cache/caustic")));
        assert_eq!(folder_from(None, None, None), None);
    }

    #[test]
    fn only_whole_framed_files_reach_the_driver() {
        let data = b"pipeline bytes".to_vec();
        let file = framed(&data);
        assert_eq!(payload(&file), Some(&data[..]));
        assert_eq!(payload(&file[..file.len() - 1]), None, "truncated");
        let mut damaged = file.clone();
        *damaged.last_mut().unwrap() ^= 1;
        assert_eq!(payload(&damaged), None, "a flipped bit");
        let mut foreign = file.clone();
        foreign[0] = b'X';
        assert_eq!(payload(&foreign), None, "another program's file");
        assert_eq!(payload(&data), None, "unframed wgpu data");
        assert_eq!(payload(b""), None);
    }

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let folder = std::env::temp_dir().join(format!("caustic-pipeline-cache-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        assert_eq!(read_cache(&folder), None, "a folder is not a cache");
        assert_eq!(read_cache(&folder.join("missing")), None);
        let file = folder.join("cache");
        std::fs::write(&file, b"abc").unwrap();
        assert_eq!(read_cache(&file).as_deref(), Some(&b"abc"[..]));
        if Path::new("/dev/zero").exists() {
            assert_eq!(read_cache(Path::new("/dev/zero")), None, "a device is not a cache");
        }
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
