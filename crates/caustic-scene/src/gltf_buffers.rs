//! Reading what glTF buffer and image URIs name, in place of the glTF crate's importer.
//!
//! gltf 1.4's `import_buffers` percent-decodes a relative URI with `unwrap` (a panic when the
//! decoded bytes are not UTF-8, e.g. `"%ff"`), reads whatever the URI names to its end (a URI
//! naming `/dev/zero` read forever, eating gigabytes a second) and follows `..` and absolute
//! `file:` paths anywhere. Here every file a URI names is resolved inside the model's folder
//! and read within the size limit by [`InputLimits`]; data URIs and the GLB binary chunk are
//! decoded by the crate, which reads no file for them.

use crate::input_file::model_folder;
use crate::{InputLimits, SceneError};
use std::path::{Path, PathBuf};

/// The data of every buffer of `document` (loaded from `path`, `blob` its GLB binary chunk),
/// each padded to a multiple of 4 bytes as the crate's importer does; a buffer shorter than
/// its declared length is an error naming it.
pub(crate) fn load_buffers(
    path: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    limits: &InputLimits,
) -> Result<Vec<gltf::buffer::Data>, SceneError> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let index = buffer.index();
        let fail = |message: String| SceneError::file(path, format!("cannot load buffers: buffer {index}: {message}"));
        let mut data = match buffer.source() {
            gltf::buffer::Source::Uri(uri) => uri_bytes(path, uri, limits).map_err(fail)?,
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| fail("the GLB binary chunk is missing".to_string()))?,
        };
        if data.len() < buffer.length() {
            return Err(fail(format!("holds {} bytes, less than its length {}", data.len(), buffer.length())));
        }
        data.resize(data.len().next_multiple_of(4), 0);
        buffers.push(gltf::buffer::Data(data));
    }
    Ok(buffers)
}

/// The bytes a buffer or image URI of the glTF file `path` names: a file inside the model's
/// folder read within `limits`, or a data URI's contents.
pub(crate) fn uri_bytes(path: &Path, uri: &str, limits: &InputLimits) -> Result<Vec<u8>, String> {
    let base = path.parent().unwrap_or(Path::new(""));
    match file_of(uri)? {
        Some(name) => {
            let file = limits.resolve(&model_folder(path), base, &name).map_err(|e| e.to_string())?;
            if !file.exists() {
                return Err(format!("file '{}' does not exist", file.display()));
            }
            limits.read(&file).map(|bytes| bytes.to_vec()).map_err(|e| e.to_string())
        }
        None => gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), None).map(|data| data.0).map_err(|e| format!("cannot be read: {e}")),
    }
}

/// The file a URI names, as gltf 1.4 reads it: `file:` URIs as they are, other URIs with a
/// scheme (data URIs) none, the rest percent-decoded (relative to the glTF file's folder).
fn file_of(uri: &str) -> Result<Option<PathBuf>, String> {
    if uri.contains(':') {
        let file = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:"));
        return Ok(file.map(PathBuf::from));
    }
    let decoded = percent_decode(uri).ok_or_else(|| format!("URI '{uri}' does not decode to UTF-8"))?;
    Ok(Some(PathBuf::from(decoded)))
}

/// `%XX` escapes replaced by their bytes, or `None` when the result is not UTF-8.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes.get(i + 1..i + 3).and_then(|h| std::str::from_utf8(h).ok()).and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                out.push(byte);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok()
}
