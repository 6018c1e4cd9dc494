//! Reading input files safely: every file a loader reads (scene files and the files they
//! `source`, OBJ material libraries, PLY, glTF files with their buffers and images, textures,
//! environment maps) goes through [`InputLimits`].
//!
//! Files from the internet can name anything. A file must be a regular file (a device such as
//! `/dev/zero`, a FIFO or a folder is refused before it is opened, so nothing blocks or reads
//! forever) no larger than [`InputLimits::max_file_size`] (a 20 GB sparse file is refused
//! before a byte is read). A file a model refers to (a glTF buffer or image URI, an OBJ
//! `mtllib` or `map_Kd`, a scene script's `source` or environment map) must resolve, symbolic
//! links followed, inside the model's own folder: no absolute paths and no `..` that leaves
//! it, unless [`InputLimits::allow_any_path`] is set. Errors name the file and, where an option
//! lifts the limit, the option.

use crate::SceneError;
use std::ffi::OsString;
use std::fs::{File, Metadata};
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// The default largest input file, 4 GiB: above any mesh or texture Caustic can render (its
/// triangle limit is 2^27), far below what a runaway read would eat.
pub const DEFAULT_MAX_FILE_SIZE: u64 = 4 << 30;

/// How the command line raises the size limit, for messages.
pub const MAX_FILE_SIZE_OPTION: &str = "--max-file-size BYTES or CAUSTIC_MAX_FILE_SIZE";

/// How the command line lifts the folder confinement, for messages.
pub const ANY_PATH_OPTION: &str = "--allow-any-path";

/// What input files may be: how large, and where the files a model refers to may lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputLimits {
    /// The largest file read, in bytes.
    pub max_file_size: u64,
    /// Whether files a model refers to may lie anywhere (absolute paths, `..` out of the
    /// model's folder); otherwise they must resolve inside the model's folder.
    pub allow_any_path: bool,
}

impl Default for InputLimits {
    fn default() -> Self {
        InputLimits { max_file_size: DEFAULT_MAX_FILE_SIZE, allow_any_path: false }
    }
}

/// Why an input file was refused or could not be read, naming the file.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}", path = .path.display())]
pub struct InputError {
    /// The file concerned.
    pub path: PathBuf,
    /// What is wrong with it.
    pub message: String,
}

impl InputError {
    fn new(path: &Path, message: impl Into<String>) -> InputError {
        InputError { path: path.to_path_buf(), message: message.into() }
    }
}

impl From<InputError> for SceneError {
    fn from(error: InputError) -> SceneError {
        SceneError::File { path: error.path, message: error.message }
    }
}

impl InputLimits {
    /// Opens `path` for reading after checking that it is a regular file within the size
    /// limit; the reader stops one byte past the limit, so a file that grows while it is read
    /// is still bounded (see [`InputLimits::read`]).
    pub fn open(&self, path: &Path) -> Result<std::io::Take<File>, InputError> {
        // Checked before opening: opening a FIFO blocks until someone writes to it.
        let metadata = std::fs::metadata(path).map_err(|e| InputError::new(path, format!("cannot read: {e}")))?;
        self.check(path, &metadata)?;
        let file = File::open(path).map_err(|e| InputError::new(path, format!("cannot open: {e}")))?;
        let metadata = file.metadata().map_err(|e| InputError::new(path, format!("cannot read: {e}")))?;
        self.check(path, &metadata)?;
        Ok(file.take(self.max_file_size.saturating_add(1)))
    }

    /// Reads the whole of `path` as [`InputLimits::open`] allows.
    pub fn read(&self, path: &Path) -> Result<Vec<u8>, InputError> {
        let mut reader = self.open(path)?;
        let expected = reader.get_ref().metadata().map_or(0, |m| m.len()).min(self.max_file_size);
        let mut bytes = Vec::with_capacity(usize::try_from(expected).unwrap_or(0));
        reader.read_to_end(&mut bytes).map_err(|e| InputError::new(path, format!("cannot read: {e}")))?;
        if bytes.len() as u64 > self.max_file_size {
            return Err(InputError::new(
                path,
                format!("grew past the input size limit of {} bytes while being read (raise it with {MAX_FILE_SIZE_OPTION})", self.max_file_size),
            ));
        }
        Ok(bytes)
    }

    /// Reads `path` as UTF-8 text, as [`InputLimits::read`].
    pub fn read_to_string(&self, path: &Path) -> Result<String, InputError> {
        String::from_utf8(self.read(path)?).map_err(|e| InputError::new(path, format!("is not UTF-8 text (byte {})", e.utf8_error().valid_up_to())))
    }

    /// Refuses what is not a regular file or is larger than the limit.
    /// Checks `path` as [`InputLimits::open`] does (a regular file within the size limit)
    /// without opening it, for readers that open the file themselves (images, partial images).
    pub fn check_file(&self, path: &Path) -> Result<(), InputError> {
        let metadata = std::fs::metadata(path).map_err(|e| InputError::new(path, format!("cannot open: {e}")))?;
        self.check(path, &metadata)
    }

    fn check(&self, path: &Path, metadata: &Metadata) -> Result<(), InputError> {
        if !metadata.is_file() {
            return Err(InputError::new(path, format!("is not a regular file ({}): refused", file_kind(metadata))));
        }
        if metadata.len() > self.max_file_size {
            let message =
                format!("is {} bytes, over the input size limit of {} bytes (raise it with {MAX_FILE_SIZE_OPTION})", metadata.len(), self.max_file_size);
            return Err(InputError::new(path, message));
        }
        Ok(())
    }

    /// The file `name` refers to, written in a file in folder `dir`, for a model whose own
    /// folder is `root`: `dir` joined with `name`. Unless [`InputLimits::allow_any_path`], the
    /// name must be relative and the path, symbolic links resolved, must lie inside `root`.
    /// The file need not exist (the reader reports that).
    pub fn resolve(&self, root: &Path, dir: &Path, name: &Path) -> Result<PathBuf, InputError> {
        let joined = dir.join(name);
        if self.allow_any_path {
            return Ok(joined);
        }
        if name.has_root() || name.is_absolute() {
            let message =
                format!("is an absolute path: files a model refers to must lie inside its folder {} (allow any path with {ANY_PATH_OPTION})", root.display());
            return Err(InputError::new(&joined, message));
        }
        if !real_path(&joined).starts_with(real_path(root)) {
            let message = format!("lies outside the model's folder {} (allow any path with {ANY_PATH_OPTION})", root.display());
            return Err(InputError::new(&joined, message));
        }
        Ok(joined)
    }

    /// Checks an output file a scene script names (`output`, `preview`): unless
    /// [`InputLimits::allow_any_path`], it must be relative and lie, symbolic links resolved,
    /// inside `folder` (the folder of `-o`, else the current folder), so that a downloaded
    /// script cannot overwrite files elsewhere.
    pub fn check_output(&self, folder: &Path, name: &Path) -> Result<(), InputError> {
        if self.allow_any_path {
            return Ok(());
        }
        if name.has_root() || name.is_absolute() {
            let message = format!(
                "a scene's output is an absolute path: it must lie inside the output folder {} (allow any path with {ANY_PATH_OPTION})",
                folder.display()
            );
            return Err(InputError::new(name, message));
        }
        if !real_path(&folder.join(name)).starts_with(real_path(folder)) {
            let message = format!("a scene's output lies outside the output folder {} (allow any path with {ANY_PATH_OPTION})", folder.display());
            return Err(InputError::new(name, message));
        }
        Ok(())
    }
}

/// The folder a model file's references are confined to: its own folder (the current
/// folder for a bare file name).
pub fn model_folder(model: &Path) -> PathBuf {
    match model.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `path` made absolute with symbolic links resolved: its longest existing ancestor
/// canonicalised, the rest (which does not exist) appended with `.` and `..` applied.
fn real_path(path: &Path) -> PathBuf {
    let mut head = if path.as_os_str().is_empty() { PathBuf::from(".") } else { path.to_path_buf() };
    let mut tail: Vec<Option<OsString>> = Vec::new();
    let mut out = loop {
        if let Ok(real) = head.canonicalize() {
            break real;
        }
        match head.components().next_back() {
            Some(Component::Normal(name)) => tail.push(Some(name.to_os_string())),
            Some(Component::ParentDir) => tail.push(None),
            Some(Component::CurDir) => {}
            // A root or prefix that does not canonicalise: nothing to resolve.
            Some(Component::RootDir | Component::Prefix(_)) | None => break std::env::current_dir().unwrap_or_default(),
        }
        if !head.pop() || head.as_os_str().is_empty() {
            break std::env::current_dir().unwrap_or_default();
        }
    };
    for part in tail.into_iter().rev() {
        match part {
            Some(name) => out.push(name),
            None => {
                out.pop();
            }
        }
    }
    out
}

/// A file type in words, for messages.
fn file_kind(metadata: &Metadata) -> &'static str {
    let kind = metadata.file_type();
    if kind.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("caustic-input-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn devices_folders_and_large_files_are_refused() {
        let limits = InputLimits::default();
        let dir = scratch("refused");
        for (path, expected) in [(Path::new("/dev/zero"), "a character device"), (dir.as_path(), "a folder")] {
            let error = limits.read(path).unwrap_err().to_string();
            println!("{error}");
            assert!(error.contains(expected) && error.contains(&path.display().to_string()), "{error}");
        }
        let sparse = dir.join("sparse.obj");
        File::create(&sparse).unwrap().set_len(DEFAULT_MAX_FILE_SIZE + 1).unwrap();
        let error = limits.read(&sparse).unwrap_err().to_string();
        println!("{error}");
        assert!(error.contains("over the input size limit") && error.contains("--max-file-size"), "{error}");
        let small = InputLimits { max_file_size: 4, ..limits };
        std::fs::write(dir.join("five"), b"12345").unwrap();
        assert!(small.read(&dir.join("five")).is_err());
        std::fs::write(dir.join("four"), b"1234").unwrap();
        assert_eq!(small.read(&dir.join("four")).unwrap(), b"1234");
    }

    #[test]
    fn references_stay_inside_the_model_folder() {
        let dir = scratch("confined");
        std::fs::create_dir_all(dir.join("model/sub")).unwrap();
        std::fs::write(dir.join("secret"), b"x").unwrap();
        let root = dir.join("model");
        let limits = InputLimits::default();
        assert!(limits.resolve(&root, &root, Path::new("sub/a.bin")).is_ok());
        assert!(limits.resolve(&root, &root.join("sub"), Path::new("../a.bin")).is_ok());
        for name in ["../secret", "../../../../etc/passwd", "/etc/passwd", "sub/../../secret", "missing/../../secret"] {
            let error = limits.resolve(&root, &root, Path::new(name)).unwrap_err().to_string();
            println!("{name}: {error}");
            assert!(error.contains("--allow-any-path"), "{error}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.join("secret"), root.join("link")).unwrap();
            assert!(limits.resolve(&root, &root, Path::new("link")).is_err(), "a symbolic link out of the folder");
        }
        let any = InputLimits { allow_any_path: true, ..limits };
        assert_eq!(any.resolve(&root, &root, Path::new("../secret")).unwrap(), root.join("../secret"));
    }
}
