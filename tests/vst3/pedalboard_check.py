"""Loads the bundled Papier.vst3 in pedalboard (JUCE's VST3 hosting, as DAWs use it), plays
MIDI, renders, saves and restores state, and checks what a DAW would check.

Usage: python pedalboard_check.py PATH/TO/Papier.vst3 OUT_DIR
Prints one line per check and exits non-zero on the first failure.
"""
import sys

import numpy as np
from mido import Message
from pedalboard import VST3Plugin, load_plugin

path, out_dir = sys.argv[1], sys.argv[2]


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        sys.exit(1)


# pedalboard warms an instrument up on every load and render call: it strikes middle C and waits
# for louder output, up to initialization_timeout (10 s by default). Papier's C4 is a phrase (the
# page turn, heard within 40 ms), so the default no longer waits; the test keeps a short bound
# so that a silent C4 would not make every call 10 s long (tests/vst3/pedalboard_timing.py times
# the default path).
INIT_TIMEOUT_S = 0.1

names = VST3Plugin.get_plugin_names_for_file(path)
check(names == ["Papier"], f"plugin names {names}")
p = load_plugin(path, initialization_timeout=INIT_TIMEOUT_S)
check(p.is_instrument and not p.is_effect, "Papier is an instrument")
params = p.parameters
for key in ["crumple", "slide", "lift", "twist", "size", "material", "table", "output_gain"]:
    check(any(k.startswith(key) for k in params), f"parameter {key} present")

# A gesture phrase from the README's MIDI map: grab the front edge, lift and shake by CC,
# release, reset.
msgs = [
    Message("note_on", note=50, velocity=100, time=0.05),
    Message("control_change", control=22, value=110, time=0.2),
    Message("control_change", control=24, value=90, time=0.4),
    Message("control_change", control=23, value=10, time=0.6),
    Message("note_on", note=48, velocity=64, time=0.8),
    Message("note_off", note=50, velocity=0, time=1.2),
    Message("note_on", note=36, velocity=127, time=1.5),
]
sr = 48000
for rate, block in [(44100, 512), (48000, 64), (96000, 1024)]:
    out = p(msgs, duration=2.0, sample_rate=rate, num_channels=2, buffer_size=block, reset=True)
    check(out.shape == (2, 2 * rate), f"render shape at {rate} Hz / {block}: {out.shape}")
    check(bool(np.all(np.isfinite(out))), f"finite output at {rate} Hz / {block}")
    check(float(np.max(np.abs(out))) <= 1.0, f"no clipping at {rate} Hz / {block}")

# Parameters in plain units (VST3 hosts deliver them to the processor in the next process
# call, as a DAW does while playing), then state save and restore into a fresh instance.
p.slide = 0.25
p.size = "A6"
p([], duration=0.1, sample_rate=sr, num_channels=2, reset=False)
state = p.raw_state
check(len(state) > 100, f"state of {len(state)} bytes")
q = load_plugin(path, initialization_timeout=INIT_TIMEOUT_S)
q.raw_state = state
check(abs(q.slide - 0.25) < 1e-6, f"slide restored ({q.slide})")
check(str(q.size) == "A6", f"size restored ({q.size})")
check(q.raw_state == state, "restored state re-saves byte-identically")
a = p(msgs, duration=1.0, sample_rate=sr, num_channels=2, reset=True)
b = q(msgs, duration=1.0, sample_rate=sr, num_channels=2, reset=True)
check(a.shape == b.shape and bool(np.all(np.isfinite(b))), "restored instance renders")
np.save(f"{out_dir}/pedalboard_render.npy", b)
print("RESULT: PASS")
