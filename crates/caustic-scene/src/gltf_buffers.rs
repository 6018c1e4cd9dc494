//! Checks of the files glTF buffer URIs name, made before the glTF crate reads them.
//!
//! gltf 1.4's `import_buffers` percent-decodes a relative URI with `unwrap` (a panic when the
//! decoded bytes are not UTF-8, e.g. `"%ff"`) and reads whatever the URI names to its end, so
//! a URI naming a device such as `/dev/zero` read forever, eating gigabytes a second.
//! [`check_buffer_uris`] refuses both with an error naming the buffer.

use crate::SceneError;
use std::path::{Path, PathBuf};

/// Checks every external buffer URI of `document` (loaded from `path`): it must decode to
/// UTF-8 and name a regular file or nothing (the crate reports a missing file). Data URIs and
/// the GLB binary chunk are left to the crate.
pub(crate) fn check_buffer_uris(path: &Path, document: &gltf::Document) -> Result<(), SceneError> {
    let Some(base) = path.parent() else { return Ok(()) };
    for buffer in document.buffers() {
        let gltf::buffer::Source::Uri(uri) = buffer.source() else { continue };
        let index = buffer.index();
        let file = match file_of(base, uri) {
            Ok(Some(file)) => file,
            Ok(None) => continue,
            Err(message) => return Err(SceneError::file(path, format!("cannot load buffers: buffer {index}: {message}"))),
        };
        // A missing file is left to the crate, whose error says so.
        if file.exists() && !file.is_file() {
            let message = format!("cannot load buffers: buffer {index}: '{}' is not a regular file", file.display());
            return Err(SceneError::file(path, message));
        }
    }
    Ok(())
}

/// The file a buffer URI names, resolved as gltf 1.4 does (`file:` URIs as they are, other
/// URIs with a scheme not at all, the rest percent-decoded relative to `base`).
pub(crate) fn file_of(base: &Path, uri: &str) -> Result<Option<PathBuf>, String> {
    if uri.contains(':') {
        let file = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:"));
        return Ok(file.map(PathBuf::from));
    }
    let decoded = percent_decode(uri).ok_or_else(|| format!("URI '{uri}' does not decode to UTF-8"))?;
    Ok(Some(base.join(decoded)))
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
