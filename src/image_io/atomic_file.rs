//! Atomic file replacement: write a temporary sibling, then rename it over the target.
use std::{
    ffi::OsString,
    fs::{self, File, OpenOptions},
    io::{self, BufWriter},
    path::{Path, PathBuf},
    sync::atomic::{AtomicU32, Ordering},
};

use super::ImageIoError;

/// Writes `path` through `write`, so that `path` holds either its old content or the complete
/// new content, never a partial file. On any error the temporary file is removed.
pub(crate) fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), ImageIoError>,
) -> Result<(), ImageIoError> {
    let (temp_path, file) = create_temp_sibling(path)?;
    let result = finish(path, &temp_path, file, write);
    if result.is_err() {
        // Best effort: the original error matters more than a failed cleanup.
        let _ = fs::remove_file(&temp_path);
    }
    result
}

/// Writes `bytes` to `path` atomically: any file, images and JSON reports alike.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), ImageIoError> {
    use std::io::Write;
    write_atomically(path, |w| {
        w.write_all(bytes).map_err(|e| ImageIoError::io(path, "cannot write temporary file", e))
    })
}

fn finish(
    path: &Path,
    temp_path: &Path,
    file: File,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), ImageIoError>,
) -> Result<(), ImageIoError> {
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer
        .into_inner()
        .map_err(|e| ImageIoError::io(path, "cannot write temporary file", e.into_error()))?;
    // Without syncing before the rename, a crash could leave the renamed file with no data on
    // some file systems (e.g. ext4 with delayed allocation).
    file.sync_all().map_err(|e| ImageIoError::io(path, "cannot sync temporary file", e))?;
    drop(file);
    fs::rename(temp_path, path).map_err(|e| ImageIoError::io(path, "cannot rename temporary file onto", e))
}

/// Creates `.NAME.PID-N.tmp` next to `path`: same directory, so the rename cannot cross file
/// systems; hidden and not ending in the image extension, so globs skip it.
fn create_temp_sibling(path: &Path) -> Result<(PathBuf, File), ImageIoError> {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let file_name = path
        .file_name()
        .ok_or_else(|| ImageIoError::io(path, "cannot write", io::Error::other("path has no file name")))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut temp_name = OsString::from(".");
        temp_name.push(file_name);
        temp_name.push(format!(".{}-{n}.tmp", std::process::id()));
        let temp_path = dir.join(temp_name);
        // create_new: never clobber a file another writer (or a crashed run) left behind.
        match OpenOptions::new().write(true).create_new(true).open(&temp_path) {
            Ok(file) => return Ok((temp_path, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(ImageIoError::io(path, "cannot create temporary file in its directory", e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("wavetrace-atomic-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<OsString> {
        let mut names: Vec<_> = fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        names.sort();
        names
    }

    #[test]
    fn failed_write_keeps_old_content_and_removes_temp() {
        let dir = temp_dir("fail");
        let path = dir.join("a.bin");
        fs::write(&path, b"old").unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(&[0; 100_000]).unwrap();
            Err(ImageIoError::unsupported(&path, "boom"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("boom"));
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert_eq!(entries(&dir), [OsString::from("a.bin")]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn successful_write_replaces_content() {
        let dir = temp_dir("ok");
        let path = dir.join("a.bin");
        fs::write(&path, b"old").unwrap();
        write_atomically(&path, |w| w.write_all(b"new").map_err(|e| ImageIoError::io(&path, "w", e)))
            .unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
        assert_eq!(entries(&dir), [OsString::from("a.bin")]);
        fs::remove_dir_all(&dir).unwrap();
    }
}
