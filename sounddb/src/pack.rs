//! # Single-file pack of a database folder
//!
//! The plugin embeds its default database in the binary (`include_bytes!`), so the folder is
//! packed into one byte string and read back through the *same* loader and validation as a folder
//! ([`crate::Database::from_pack`]). Layout (all integers little-endian):
//!
//! ```text
//! magic   8 bytes  "PAPIERDB"
//! version u32      1
//! count   u32      number of files
//! count × { name_len u32, name (UTF-8, '/'-separated relative path), data_len u64, data }
//! ```
//!
//! Reading never panics: every length is checked against the remaining bytes.

use std::collections::BTreeMap;

use crate::DbError;
use crate::bytes::{ByteReader, PutLe};

/// Magic bytes at the start of a pack.
pub const MAGIC: &[u8; 8] = b"PAPIERDB";
/// Pack layout version.
pub const PACK_VERSION: u32 = 1;

/// Where the loader reads files from.
pub trait FileSource {
    /// Reads a file by its `/`-separated path relative to the database root.
    fn read(&self, rel: &str) -> std::io::Result<Vec<u8>>;
    /// All file paths (relative, `/`-separated), for the "unreferenced file" check.
    fn list(&self) -> Vec<String>;
    /// A display path for messages.
    fn display_path(&self, rel: &str) -> std::path::PathBuf;
}

/// A folder on disk.
pub struct DirSource {
    /// The database folder.
    pub root: std::path::PathBuf,
}

impl FileSource for DirSource {
    fn read(&self, rel: &str) -> std::io::Result<Vec<u8>> {
        if rel.split('/').any(|c| c == "..") || rel.starts_with('/') {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "paths must stay inside the database folder",
            ));
        }
        std::fs::read(self.root.join(rel))
    }

    fn list(&self) -> Vec<String> {
        let mut out = Vec::new();
        list_dir(&self.root, "", &mut out, 0);
        out.sort();
        out
    }

    fn display_path(&self, rel: &str) -> std::path::PathBuf {
        self.root.join(rel)
    }
}

fn list_dir(dir: &std::path::Path, prefix: &str, out: &mut Vec<String>, depth: usize) {
    if depth > 4 {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        let rel = if prefix.is_empty() {
            name.clone()
        } else {
            format!("{prefix}/{name}")
        };
        match e.file_type() {
            Ok(t) if t.is_dir() => list_dir(&e.path(), &rel, out, depth + 1),
            Ok(t) if t.is_file() => out.push(rel),
            _ => {}
        }
    }
}

/// An in-memory set of files (a parsed pack, or a database about to be written).
#[derive(Clone, Debug, Default)]
pub struct MemSource {
    /// Name shown in messages.
    pub label: String,
    /// Files by relative path.
    pub files: BTreeMap<String, Vec<u8>>,
}

impl FileSource for MemSource {
    fn read(&self, rel: &str) -> std::io::Result<Vec<u8>> {
        self.files.get(rel).cloned().ok_or_else(|| {
            std::io::Error::new(std::io::ErrorKind::NotFound, format!("{rel} not in pack"))
        })
    }

    fn list(&self) -> Vec<String> {
        self.files.keys().cloned().collect()
    }

    fn display_path(&self, rel: &str) -> std::path::PathBuf {
        std::path::PathBuf::from(format!("{}:{rel}", self.label))
    }
}

/// Packs files into one byte string.
pub fn pack(files: &BTreeMap<String, Vec<u8>>) -> Vec<u8> {
    let total: usize = files.iter().map(|(k, v)| k.len() + v.len() + 12).sum();
    let mut out = Vec::with_capacity(16 + total);
    out.extend_from_slice(MAGIC);
    out.put_u32(PACK_VERSION);
    out.put_u32(files.len() as u32);
    for (name, data) in files {
        out.put_str(name);
        out.put_u64(data.len() as u64);
        out.extend_from_slice(data);
    }
    out
}

/// Unpacks a byte string made by [`pack`].
pub fn unpack(bytes: &[u8], label: &str) -> Result<MemSource, DbError> {
    let mut r = ByteReader::new(bytes, DbError::BadPack);
    if r.take(8)? != MAGIC {
        return Err(DbError::BadPack("missing PAPIERDB magic".into()));
    }
    let version = r.u32()?;
    if version != PACK_VERSION {
        return Err(DbError::BadPack(format!(
            "pack version {version}, this build reads {PACK_VERSION}"
        )));
    }
    let count = r.u32()? as usize;
    let mut files = BTreeMap::new();
    for i in 0..count {
        let name = r
            .str()
            .map_err(|_| DbError::BadPack(format!("file {i}: name is damaged or not UTF-8")))?;
        let len = r.len()?;
        let data = r.take(len)?.to_vec();
        files.insert(name, data);
    }
    if r.remaining() != 0 {
        return Err(DbError::BadPack(format!(
            "{} trailing bytes after {count} files",
            r.remaining()
        )));
    }
    Ok(MemSource {
        label: label.to_string(),
        files,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_truncation() {
        let mut files = BTreeMap::new();
        files.insert("manifest.toml".to_string(), b"x = 1".to_vec());
        files.insert("crumple/a.wav".to_string(), vec![1, 2, 3]);
        let bytes = pack(&files);
        let src = unpack(&bytes, "test").unwrap();
        assert_eq!(src.files, files);
        for cut in [0, 5, 12, 20, bytes.len() - 1] {
            assert!(matches!(
                unpack(&bytes[..cut], "t"),
                Err(DbError::BadPack(_))
            ));
        }
        let mut extra = bytes.clone();
        extra.push(0);
        assert!(unpack(&extra, "t").is_err());
    }
}
