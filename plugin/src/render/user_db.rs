//! # A user's sound database folder, loaded and prepared for a sample rate
//!
//! Shared by the plugin (its loader thread, `crate::db_loader`) and `papier-render --db`: the
//! folder is read and validated by [`sounddb::SoundDb::load`] and resampled to the host's rate;
//! a database without a usable unit is refused, a partial one plays with warnings. Allocates
//! (never call it on the audio thread).

use std::path::Path;
use std::sync::Arc;

use sounddb::SoundDb;

/// What a loaded user database holds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UserDbInfo {
    /// Its display name.
    pub name: String,
    /// Units it holds.
    pub units: usize,
    /// What the loader warned about (a partial database still plays).
    pub warnings: Vec<String>,
}

/// Loads and prepares the user database in `path` for `sample_rate_hz`; the error is one line.
pub fn load(path: &Path, sample_rate_hz: f64) -> Result<(Arc<SoundDb>, UserDbInfo), String> {
    let (db, warnings) =
        SoundDb::load(path, sample_rate_hz).map_err(|e| one_line(&e.to_string()))?;
    if db.num_units() == 0 {
        return Err("the database holds no usable units".into());
    }
    let info = UserDbInfo {
        name: db.info().name.clone(),
        units: db.num_units(),
        warnings: warnings.iter().map(|w| w.to_string()).collect(),
    };
    Ok((Arc::new(db), info))
}

/// An error message on one line (the editor's status line, `papier-render`'s error): a TOML
/// parser's multi-line report keeps its text and drops its source excerpt and caret.
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| {
            let excerpt = l
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start();
            !l.is_empty() && !excerpt.starts_with('|')
        })
        .collect::<Vec<_>>()
        .join(": ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Detects a multi-line error (the TOML parser's source excerpt) reaching the one-line
    /// status, and a one-line error that is altered.
    #[test]
    fn errors_are_one_line() {
        let toml = "manifest m.toml is not valid: TOML parse error at line 3, column 13\n  |\n3 | \
                    name = [oops\n  |             ^\nunclosed array, expected `]`\n";
        assert_eq!(
            one_line(toml),
            "manifest m.toml is not valid: TOML parse error at line 3, column 13: \
             unclosed array, expected `]`"
        );
        let plain = "sound database folder /x does not exist or is not a folder";
        assert_eq!(one_line(plain), plain);
    }
}
