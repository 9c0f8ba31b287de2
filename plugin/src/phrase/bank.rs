//! The phrases an instance plays: the factory set (embedded) and the user's folder.
//!
//! Factory phrases: six written for performing (`plugin/phrases/*.toml`, C4–F4) and the sixteen
//! seed scenes (`sim-core/scenarios/*.toml`, F#4–A5), each on a fresh sheet. The user's phrases
//! are the `*.toml` files of a folder, each with its `[phrase]` table; a user phrase on a
//! factory phrase's note replaces it, and a damaged file is reported (one line) while the others
//! still load. Built off the audio thread (at activation, on the editor's reload).

use std::path::Path;

use sim_core::script::Script;

use super::spec::{NoteOffRule, Phrase, PhraseStart};

/// The factory phrases written for performing: (file name, text).
const FACTORY: [(&str, &str); 6] = [
    (
        "page_turn.toml",
        include_str!("../../phrases/page_turn.toml"),
    ),
    (
        "crumple_receipt.toml",
        include_str!("../../phrases/crumple_receipt.toml"),
    ),
    (
        "quick_tear.toml",
        include_str!("../../phrases/quick_tear.toml"),
    ),
    (
        "slow_tear.toml",
        include_str!("../../phrases/slow_tear.toml"),
    ),
    (
        "slide_table.toml",
        include_str!("../../phrases/slide_table.toml"),
    ),
    (
        "shake_out.toml",
        include_str!("../../phrases/shake_out.toml"),
    ),
];

/// The seed scenes as phrases: (name, text), on consecutive notes from [`FIRST_SCENE_NOTE`].
const SCENES: [(&str, &str); 16] = [
    (
        "c1 first sharp feature",
        include_str!("../../../sim-core/scenarios/c1_first_sharp_feature.toml"),
    ),
    (
        "c2 moebius twist",
        include_str!("../../../sim-core/scenarios/c2_moebius_twist.toml"),
    ),
    (
        "c3 unload after singularity",
        include_str!("../../../sim-core/scenarios/c3_unload_after_singularity.toml"),
    ),
    (
        "c4 double bend",
        include_str!("../../../sim-core/scenarios/c4_double_bend.toml"),
    ),
    (
        "c5 full crumple",
        include_str!("../../../sim-core/scenarios/c5_full_crumple.toml"),
    ),
    (
        "c6 four corner flip",
        include_str!("../../../sim-core/scenarios/c6_four_corner_flip.toml"),
    ),
    (
        "s1 slide, release, pinch",
        include_str!("../../../sim-core/scenarios/s1_slide_release_pinch.toml"),
    ),
    (
        "s2 shake",
        include_str!("../../../sim-core/scenarios/s2_shake.toml"),
    ),
    (
        "s3 wiggle near wall",
        include_str!("../../../sim-core/scenarios/s3_wiggle_near_wall.toml"),
    ),
    (
        "s4 crumple",
        include_str!("../../../sim-core/scenarios/s4_crumple.toml"),
    ),
    (
        "s5 fold and revert",
        include_str!("../../../sim-core/scenarios/s5_fold_and_revert.toml"),
    ),
    (
        "s6 slide on table",
        include_str!("../../../sim-core/scenarios/s6_slide_on_table.toml"),
    ),
    (
        "t1 two-hand tear",
        include_str!("../../../sim-core/scenarios/t1_two_hand_tear.toml"),
    ),
    (
        "t2 steered tear",
        include_str!("../../../sim-core/scenarios/t2_steered_tear.toml"),
    ),
    (
        "t3 equal pull",
        include_str!("../../../sim-core/scenarios/t3_pull_equal.toml"),
    ),
    (
        "t4 unequal pull",
        include_str!("../../../sim-core/scenarios/t4_pull_unequal.toml"),
    ),
];

/// The `*.toml` files of a folder listing, sorted by path (shared with [`crate::preset`]).
pub(crate) fn toml_files(entries: std::fs::ReadDir) -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("toml"))
        })
        .collect();
    files.sort();
    files
}

/// Note of the first seed scene (F#4).
pub const FIRST_SCENE_NOTE: u8 = 66;

/// A set of phrases, at most one per note.
#[derive(Debug, Default)]
pub struct PhraseBank {
    phrases: Vec<Phrase>,
    by_note: Vec<Option<u16>>,
    /// Files refused while loading (one line each).
    pub errors: Vec<String>,
}

impl PhraseBank {
    /// A bank of these phrases (a later phrase on a note replaces an earlier one).
    pub fn from_phrases(list: Vec<Phrase>) -> Self {
        let mut bank = Self {
            phrases: Vec::with_capacity(list.len()),
            by_note: vec![None; 128],
            errors: Vec::new(),
        };
        for p in list {
            bank.insert(p);
        }
        bank
    }

    fn insert(&mut self, p: Phrase) {
        let note = usize::from(p.note.min(127));
        match self.by_note[note] {
            Some(i) => self.phrases[usize::from(i)] = p,
            None => {
                self.by_note[note] = Some(self.phrases.len() as u16);
                self.phrases.push(p);
            }
        }
    }

    /// The factory phrases.
    pub fn factory() -> Self {
        let mut list = Vec::with_capacity(FACTORY.len() + SCENES.len());
        for (file, text) in FACTORY {
            let name = file.trim_end_matches(".toml");
            let mut p = Phrase::parse(text, file, name).expect("factory phrases parse");
            p.source = format!("factory ({file})");
            list.push(p);
        }
        for (i, (name, text)) in SCENES.into_iter().enumerate() {
            let script = Script::parse(text).expect("seed scenes parse");
            let mut header = toml::Table::new();
            header.insert(
                "note".into(),
                toml::Value::Integer(i64::from(FIRST_SCENE_NOTE) + i as i64),
            );
            let mut p = Phrase::from_script(&script, &header, "factory", name, true)
                .expect("seed scenes are phrases");
            p.start = PhraseStart::Fresh;
            p.note_off = NoteOffRule::Finish;
            list.push(p);
        }
        Self::from_phrases(list)
    }

    /// The factory phrases and the `*.toml` files of `dir` (sorted by name; a missing folder is
    /// no error, an unreadable one is).
    pub fn with_folder(dir: &Path) -> Self {
        let mut bank = Self::factory();
        let entries = match std::fs::read_dir(dir) {
            Ok(e) => e,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return bank,
            Err(e) => {
                bank.errors.push(format!(
                    "{}: cannot read the phrase folder: {e}",
                    dir.display()
                ));
                return bank;
            }
        };
        let files = toml_files(entries);
        for path in files {
            let shown = path.display().to_string();
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().replace('_', " "))
                .unwrap_or_default();
            let text = match std::fs::read(&path)
                .map_err(|e| e.to_string())
                .and_then(|b| String::from_utf8(b).map_err(|_| "not UTF-8 text".to_string()))
            {
                Ok(t) => t,
                Err(e) => {
                    bank.errors.push(format!("{shown}: {e}"));
                    continue;
                }
            };
            match Phrase::parse(&text, &shown, &name) {
                Ok(p) => bank.insert(p),
                Err(e) => bank.errors.push(e.to_string()),
            }
        }
        bank
    }

    /// The phrases, in note-insertion order.
    pub fn phrases(&self) -> &[Phrase] {
        &self.phrases
    }

    /// Index of the phrase on `note`.
    pub fn index_of(&self, note: u8) -> Option<usize> {
        self.by_note
            .get(usize::from(note))
            .copied()
            .flatten()
            .map(usize::from)
    }

    /// The phrase on `note`.
    pub fn get(&self, note: u8) -> Option<&Phrase> {
        self.index_of(note).map(|i| &self.phrases[i])
    }

    /// The phrases sorted by note.
    pub fn by_note(&self) -> impl Iterator<Item = &Phrase> {
        self.by_note
            .iter()
            .flatten()
            .map(|i| &self.phrases[usize::from(*i)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factory_bank_has_every_phrase_on_its_own_note() {
        let bank = PhraseBank::factory();
        assert_eq!(bank.phrases().len(), FACTORY.len() + SCENES.len());
        assert!(bank.errors.is_empty());
        for (note, name) in [
            (60, "page turn"),
            (61, "crumple a receipt"),
            (62, "quick tear"),
            (63, "slow tear"),
            (64, "slide across the table"),
            (65, "shake out a sheet"),
            (66, "c1 first sharp feature"),
            (81, "t4 unequal pull"),
        ] {
            assert_eq!(bank.get(note).map(|p| p.name.as_str()), Some(name));
        }
        assert!(bank.get(59).is_none() && bank.get(82).is_none());
    }

    #[test]
    fn a_user_folder_adds_and_replaces_and_reports_bad_files() {
        let dir = std::env::temp_dir().join(format!("papier-phrases-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("my_crumple.toml"),
            "version = 1\n[phrase]\nnote = 60\n[[lane]]\nid = \"crumple\"\npoints = [[0, 0], [1, 1]]\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("broken.toml"),
            "version = 1\n[phrase]\nnote = 90\nnote = 91\n",
        )
        .unwrap();
        std::fs::write(dir.join("notes.txt"), "not a phrase").unwrap();
        let bank = PhraseBank::with_folder(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(bank.get(60).map(|p| p.name.as_str()), Some("my crumple"));
        assert_eq!(bank.phrases().len(), FACTORY.len() + SCENES.len());
        assert_eq!(bank.errors.len(), 1, "{:?}", bank.errors);
        assert!(bank.errors[0].contains("broken.toml") && bank.errors[0].contains("line 4"));
        let none = PhraseBank::with_folder(Path::new("/nonexistent/papier/phrases"));
        assert!(none.errors.is_empty());
    }
}
