//! Activation lifecycle in a real CLAP host: 100 activate/deactivate cycles each start exactly
//! one simulation worker thread and join it, in real-time and offline modes, with processing in
//! between. (Its own test binary, so no other test's threads are counted.)

use papier_tests::clap::{Bundle, HostEvent, serial};
use papier_tests::paths;

/// Threads of this process whose name is `papier-sim`.
fn sim_threads() -> usize {
    std::fs::read_dir("/proc/self/task")
        .expect("procfs")
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok())
        .filter(|name| name.trim() == "papier-sim")
        .count()
}

/// Waits (up to 2 s) until the worker count is `n`: a new thread names itself as it starts, and
/// a joined one leaves /proc a moment after the join returns.
fn wait_for_sim_threads(n: usize) -> usize {
    let t0 = std::time::Instant::now();
    loop {
        let c = sim_threads();
        if c == n || t0.elapsed() > std::time::Duration::from_secs(2) {
            return c;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

#[test]
fn hundred_activation_cycles_start_and_join_the_worker() {
    let _serial = serial();
    let b = Bundle::load(&paths::clap_bundle()).expect("load Papier.clap");
    let mut inst = b.instance().expect("instance");
    assert_eq!(sim_threads(), 0);
    for cycle in 0..100 {
        // Every tenth cycle runs in the host's offline render mode: the sheet is then stepped in
        // lockstep on the audio thread and no worker thread exists.
        let offline = cycle % 10 == 5;
        inst.set_offline(offline).expect("render mode");
        inst.activate(48_000.0, 256).expect("activate");
        let expected = if offline { 0 } else { 1 };
        assert_eq!(
            wait_for_sim_threads(expected),
            expected,
            "cycle {cycle}: workers while active (offline: {offline})"
        );
        inst.deactivate();
        // `pthread_join` returns when the thread clears its tid on exit, a moment before the
        // kernel removes its /proc entry, so the count is awaited; a worker that was not stopped
        // would run on and still be counted after the wait.
        assert_eq!(
            wait_for_sim_threads(0),
            0,
            "cycle {cycle}: worker joined on deactivate"
        );
        if cycle % 10 == 0 {
            // Process in between, with a grab.
            let (l, _) = inst
                .render(
                    48_000.0,
                    256,
                    &[],
                    4_800,
                    &[HostEvent::NoteOn {
                        at: 100,
                        key: 55,
                        velocity: 1.0,
                    }],
                )
                .expect("render");
            assert_eq!(l.len(), 4_800);
            // The render deactivated the plugin; its worker's /proc entry may outlive the join
            // by a moment (see above), so this count is awaited too.
            assert_eq!(
                wait_for_sim_threads(0),
                0,
                "cycle {cycle}: worker joined after the render"
            );
        }
    }
    drop(inst);
    assert_eq!(
        sim_threads(),
        0,
        "no worker left after the instance is destroyed"
    );
}
