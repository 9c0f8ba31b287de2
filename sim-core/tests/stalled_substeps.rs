//! Regression tests of what the sim does when the Newton solve stalls or ends at its cap, or a
//! hand's jump turns a triangle over: pinning (`sim_core::physics::newton`, "Pinning"), solving
//! the substep again from rest with the hands held back (`sim_core::sim`, "A substep solved
//! again") and solving it as shorter substeps (`sim_core::sim`, "A substep solved as shorter
//! ones").
//!
//! The fixtures are sheets saved just before a failing frame of the hostile stress sessions
//! `papier-lab stress --seed S --sessions 1`, written by
//! `cargo run --release -p papier-lab -- stress-fixture S FRAME OUT.json`:
//! - seed 2 after frame 6 452 (10⁴-frame session): with neither remedy the next frame stalled
//!   after 5 iterations and 70 halvings and ended with a triangle next to a hand stretched to
//!   2.07× its length (strain 1.065 > `MAX_STRAIN`); pinning ends it at 0.699, solving it
//!   again from rest gains too little to stand, and solving it as shorter substeps ends it at
//!   0.231;
//! - seed 4 after frame 33 201 (the long run's session 3): 2.80 with pinning alone (a vertex
//!   pinned where the predictor had carried it, next to a small triangle a hand held), 2.23
//!   with neither, 0.047 solved again;
//! - seed 11 after frame 24 680 (the long run's session 10): 1.081 with pinning alone, or with
//!   neither, 0.891 solved again;
//! - seed 14 after frame 48 656 (the long run's session 13): the next frame's left hand grabs
//!   (`Grab { slot: Left, grip: 0.78670144 }`, the stream's command at frame 48 657) and its
//!   held vertex's jump turns the small triangle [89, 22, 15] beside an inserted vertex over;
//!   solved again with the hands held back, nothing turns over.
//! - seeds 5, 8, 14, 19 and 20 after frames 39 736, 12 310, 29 766, 10 611 and 27 780 (the long
//!   run of 2026-12-01, with reused factorizations): the next frame's solve ends short of its
//!   solution (at its iteration cap; seeds 14 and 20 pinned) with the sheet strained to 1.208,
//!   1.248, 1.459, 1.006 and 1.786. Solved again as shorter substeps (`sim_core::sim`, "A
//!   substep solved as shorter ones") they end at 0.203, 0.597, 0.438, 0.164 and 0.239. Seeds
//!   14 and 20 need the ladder and the advancing orientation reference: as 2 substeps they
//!   stay strained, and their best splits turn regions of the sheet by more than 90° over the
//!   frame, each substep by less;
//! - seed 15 after frame 23 274 (the same run): the next frame turns a small triangle
//!   (1.4 cm², beside a held vertex) over by 112° at strain 0.041, and solving it again from
//!   rest with the hands held back turns it over too; as shorter substeps nothing turns over;
//! - seed 20 after frame 31 628 (the long run of 2026-12-01, evening), saved with the session's
//!   room: a slipped hand's offset turns a triangle over in every split unless it is faded out
//!   over the split;
//! - seed 19 after frame 35 370, saved with its room from the stream with the depth limit's
//!   strain guard off: the next frame's depth limit would stretch a triangle to 1.201.
//!
//! Each test fails with the remedy it names removed (checked: without pinning the first test
//! finds no pinned substep — solving again rescues that frame too — and without solving again
//! the second fails on seed 4's strain and the third on seed 14's turned triangle; without the
//! split the fourth fails on each of its five fixtures' strain and the fifth on the turned
//! triangle; without the faded second ladder the sixth fails on the turned triangle, and
//! without the depth limit's strain guard the seventh on the strain bound).

mod common;

use sim_core::control::{Command, GrabSlot};
use sim_core::sim::{FrameOutput, FrameStats, Sim};
use sim_core::stress::MAX_STRAIN;

/// Steps `sim` three frames; every frame keeps the stress invariants. Returns the first
/// frame's statistics.
fn three_sound_frames(mut sim: Sim) -> FrameStats {
    let mut out = FrameOutput::default();
    let mut first = None;
    for frame in 1..=3 {
        sim.step(&mut out);
        let strain = sim.metrics().max_strain;
        println!(
            "frame {frame}: strain {strain:.3}, halvings {}, pinned substeps {}, held back {}",
            out.stats.halvings, out.stats.pinned_substeps, out.stats.held_back_substeps
        );
        assert!(
            strain < MAX_STRAIN,
            "frame {frame}: strain {strain} beyond the stress bound"
        );
        assert_eq!(
            out.stats.num_flipped, 0,
            "frame {frame}: a triangle turned over"
        );
        assert!(common::positions_finite(&sim));
        first.get_or_insert(out.stats);
    }
    first.expect("three frames")
}

/// Restores each fixture and steps it three frames ([`three_sound_frames`]); `holds` must be
/// true of each one's first frame, else the test fails with `why`.
fn each_first_frame(fixtures: &[&str], holds: impl Fn(&FrameStats) -> bool, why: &str) {
    for json in fixtures {
        let first = three_sound_frames(common::restore_fixture(json));
        assert!(holds(&first), "{why}");
    }
}

#[test]
fn a_stalled_solve_pins_the_turning_triangle_and_the_sheet_follows_the_hands() {
    each_first_frame(
        &[include_str!("fixtures/stress_seed2_frame6452.json")],
        |first| first.pinned_substeps > 0,
        "the fixture no longer makes the solve pin (regenerate it)",
    );
}

#[test]
fn a_stalled_substep_that_strains_the_sheet_is_solved_again_from_rest() {
    each_first_frame(
        &[
            include_str!("fixtures/stress_seed4_frame33201.json"),
            include_str!("fixtures/stress_seed11_frame24680.json"),
        ],
        |first| first.held_back_substeps > 0,
        "the fixture no longer stalls into strain (regenerate it)",
    );
}

#[test]
fn a_substep_that_turns_a_triangle_over_is_solved_again_with_the_hands_held_back() {
    let mut sim = common::restore_fixture(include_str!("fixtures/stress_seed14_frame48656.json"));
    sim.apply(Command::Grab {
        slot: GrabSlot::Left,
        grip: 0.786_701_44,
    });
    let first = three_sound_frames(sim);
    assert!(
        first.held_back_substeps > 0,
        "the grab no longer turns a triangle over (regenerate the fixture)"
    );
}

#[test]
fn a_capped_substep_that_strains_the_sheet_is_solved_again_as_shorter_ones() {
    each_first_frame(
        &[
            include_str!("fixtures/stress_seed5_frame39736.json"),
            include_str!("fixtures/stress_seed8_frame12310.json"),
            include_str!("fixtures/stress_seed14_frame29766.json"),
            include_str!("fixtures/stress_seed19_frame10611.json"),
            include_str!("fixtures/stress_seed20_frame27780.json"),
        ],
        |first| first.split_substeps > 0,
        "the fixture's first frame no longer ends capped and strained (regenerate it)",
    );
}

#[test]
fn a_turned_triangle_that_solving_again_from_rest_turns_too_is_solved_as_shorter_substeps() {
    each_first_frame(
        &[include_str!("fixtures/stress_seed15_frame23274.json")],
        |first| first.split_substeps > 0 && first.held_back_substeps == 0,
        "the fixture's first frame no longer turns a triangle over both ways (regenerate it)",
    );
}

/// Seed 20 after frame 31 628, saved with the session's room (the first fixture that keeps it,
/// [`sim_core::stress::StressFixture`]; the sheet restored in the default room does not
/// reproduce the frame): a hand that slipped holds its vertices away from where the substep
/// starts them, and each split that moves them there in its first substep turns a triangle
/// over; faded out over the split (the second ladder) nothing turns over (checked: without the
/// second ladder this test fails on the turned triangle).
#[test]
fn a_slipped_hands_offset_is_faded_out_over_the_shorter_substeps() {
    each_first_frame(
        &[include_str!("fixtures/stress_seed20_frame31628.json")],
        |first| first.split_substeps > 0,
        "the fixture's first frame is no longer split (regenerate it)",
    );
}

/// Seed 19 after frame 35 370, saved with the session's room from a stream run with the depth
/// limit's strain guard off (`Sim::limit_penetration`; on, the stream does not reach this
/// state): the next frame's solve ends at strain 0.443, and putting a vertex deep in the table
/// back at the depth limit stretched a triangle to 1.201. The guard leaves that triangle where
/// the solve put it (checked: without the guard this test fails on the strain bound).
#[test]
fn the_depth_limit_leaves_a_triangle_it_would_strain_where_the_solve_put_it() {
    each_first_frame(
        &[include_str!("fixtures/stress_seed19_frame35370.json")],
        |first| first.max_strain <= 0.5,
        "the fixture's first frame strains the sheet beyond 0.5 (regenerate it)",
    );
}
