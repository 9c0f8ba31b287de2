"""Times Papier.vst3 in pedalboard as a user runs it (default settings): the load, and render
calls of 1 s and 4 s with nothing played and with a crumple (each call re-creates the plugin, pedalboard's `reset=True` default), and
one call without the reset. Prints the figures; asserts nothing (the machine is shared).

Usage: target/venv/bin/python tests/vst3/pedalboard_timing.py target/bundled/Papier.vst3
"""
import sys
import time

from mido import Message
from pedalboard import load_plugin

path = sys.argv[1]
started = time.time()
plugin = load_plugin(path)
print(f"load_plugin: {time.time() - started:.2f} s ({len(plugin.parameters)} parameters listed)")
take = [
    Message("note_on", note=50, velocity=100, time=0.05),
    Message("control_change", control=20, value=120, time=0.3),
]
# Nothing played (the fixed cost of a call), then a crumple take.
for midi, what in [([], "nothing played"), (take, "a crumple")]:
    for seconds, reset in [(1.0, True), (1.0, True), (4.0, True), (1.0, False)]:
        started = time.time()
        plugin(midi, duration=seconds, sample_rate=48000, num_channels=2, buffer_size=512, reset=reset)
        elapsed = time.time() - started
        print(f"call, {what}, {seconds:.0f} s of audio, reset={reset}: {elapsed:.2f} s")
