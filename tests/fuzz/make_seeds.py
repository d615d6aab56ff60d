#!/usr/bin/env python3
"""Writes the committed seed corpus of tests/fuzz (reproducible; run from anywhere).

Each target's directory gets a few ordinary inputs and every reproducer of a defect found in
the handling of untrusted input that its encoding can express (see each fuzz_*.cpp for the
encoding):
  fuzz_scene: the format's example, small scenes like those of scenes/ (one with joints, one
              with joint actions and one refused for an add_joint to a removed body), a value
              nested 100k deep, hull points of 1e300, a name with a NUL and one with an escape
              sequence;
  fuzz_hull:  a cube, points of 1e300, a needle (three points within 1e-9 m, one 10 m off);
  fuzz_narrowphase: every mode, and the 26 m box touching the 4 km box (exact doubles);
  fuzz_world: small worlds shaped after the reproducers (a stack; API calls given
              infinities and NaN). The engine-level reproducers (an infinite force freezing
              a stack, a zero quaternion, a negative dt, a spin of 1e8 rad/s) are gtests in
              api_input_test.cpp and rotation_test.cpp, where each value is exact.
  fuzz_state: a state of every shape and joint kind loaded intact (awake, and with its stack
              asleep), with a bit flipped (resealed, and not), with a double made NaN, an
              infinity, 1e300, -0 or 2e15 and a u32 made 0xFFFFFFFF, 1000 or 2^31 at a few
              offsets (resealed), and cut.
"""
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    d = os.path.join(HERE, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def u16(x):  # FuzzInput::Range's two bytes for a fraction x in [0, 1]
    return struct.pack("<H", round(x * 65535))


def raw(*xs):
    return b"".join(struct.pack("<d", x) for x in xs)


# --- fuzz_scene
example = {"format": "rengine-scene/1", "gravity": [0, -9.81, 0], "dt": 0.016666666666666666,
           "steps": 20, "bodies": [
               {"name": "ground", "shape": {"type": "box", "half_extents": [50, 0.5, 50]},
                "static": True, "position": [0, -0.5, 0]},
               {"name": "crate", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                "mass": 1.0, "position": [0, 0.5, 0], "restitution": 0.0, "friction": 0.5},
               {"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "density": 2.0,
                "position": [3, 2, 0], "ignore": ["crate"]},
               {"name": "rock", "shape": {"type": "hull", "points": [[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, -1, -1]]},
                "mass": 4.0, "position": [0, 5, 0], "responds": False}],
           "solver": {"iterations": 4, "sleeping": False}}
write("fuzz_scene", "example.json", json.dumps(example))
write("fuzz_scene", "pair.json", json.dumps({"dt": 0.01, "steps": 5, "restitution_combine": "max", "bodies": [
    {"name": "a", "shape": {"type": "sphere", "radius": 0.5}, "velocity": [3, 0, 0], "restitution": 1},
    {"name": "b", "shape": {"type": "sphere", "radius": 0.5}, "position": [2, 0, 0], "mass": 3}]}))
write("fuzz_scene", "kinds.json", json.dumps({"gravity": [0, -9.81, 0], "steps": 10, "bodies": [
    {"name": "table", "shape": {"type": "box", "half_extents": [3, 0.25, 3]}, "kind": "kinematic",
     "position": [0, -0.25, 0], "angular_velocity": [0, 1, 0], "velocity": [0, 0.5, 0]},
    {"name": "crate", "shape": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}, "position": [1, 0.25, 0],
     "linear_damping": 0.5, "angular_damping": 1, "gravity_scale": -0.5,
     "locks": {"linear": [False, False, True], "angular": [True, True, False]}},
    {"name": "floor", "shape": {"type": "sphere", "radius": 1}, "static": True, "kind": "static",
     "position": [0, -9, 0]}],
    "actions": [{"step": 3, "set_velocity": {"body": "table", "angular_velocity": [0, -2, 0]}}]}))
write("fuzz_scene", "joints.json", json.dumps({"gravity": [0, -9.81, 0], "steps": 10, "bodies": [
    {"name": "ground", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "static": True},
    {"name": "arm", "shape": {"type": "box", "half_extents": [1, 0.1, 0.1]}, "position": [1, 2, 0]},
    {"name": "bob", "shape": {"type": "sphere", "radius": 0.2}, "position": [2, 1, 0]},
    {"name": "car", "shape": {"type": "box", "half_extents": [0.5, 0.2, 0.3]}, "position": [0, 4, 0]}],
    "joints": [
        {"name": "shoulder", "type": "hinge", "a": "arm", "b": "ground", "anchor": [0, 2, 0], "axis": [0, 0, 1],
         "limits": [-1.5, 1.5], "motor": {"speed": 1, "max_force": 50}},
        {"name": "wrist", "type": "ball", "a": "bob", "b": "arm", "anchor": [2, 2, 0]},
        {"name": "rail", "type": "slider", "a": "car", "anchor": [0, 4, 0], "axis": [1, -1, 0], "limits": [-1, 1]},
        {"name": "weld", "type": "fixed", "a": "car", "b": "bob", "anchor": [1, 2.5, 0], "collide_connected": True},
        {"name": "rope", "type": "distance", "a": "bob", "anchor": [2, 1, 0], "anchor_b": [2, 5, 0],
         "min_distance": 0, "max_distance": 4.5}],
    "actions": [{"step": 5, "remove": "arm"}]}))
write("fuzz_scene", "deep_nesting.json", '{"gravity": ' + "[" * 100000 + "]" * 100000 + ', "bodies": []}')
write("fuzz_scene", "hull_1e300.json", json.dumps({"bodies": [{"name": "big", "shape": {"type": "hull", "points": [
    [1e300, 0, 0], [0, 1e300, 0], [0, 0, 1e300], [1e300, 1e300, 1e300], [0, 0, 0]]}}]}))
write("fuzz_scene", "steps_2e63.json", '{"steps": 9223372036854775807, "bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}}]}')
write("fuzz_scene", "name_nul.json", '{"bodies": [{"name": "a\\u0000b", "shape": {"type": "sphere", "radius": 1}}]}')
write("fuzz_scene", "name_escape.json", '{"bodies": [{"name": "\\u001b[2J", "shape": {"type": "sphere", "radius": 1}}]}')
# Joint actions: a ball caught by an add_joint, a rope cut by remove_joint, a joint added to a
# body an action adds, a name taken again after its joint went with its body.
write("fuzz_scene", "joint_actions.json", json.dumps({"gravity": [0, -9.81, 0], "steps": 12, "bodies": [
    {"name": "hook", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "static": True, "position": [0, 5, 0]},
    {"name": "bob", "shape": {"type": "sphere", "radius": 0.2}, "position": [1, 4, 0], "velocity": [0, 1, 0]},
    {"name": "weight", "shape": {"type": "sphere", "radius": 0.1}, "position": [3, 3, 0]}],
    "joints": [{"name": "rope", "type": "distance", "a": "weight", "anchor": [3, 3.1, 0], "anchor_b": [3, 5, 0],
                "min_distance": 0}],
    "actions": [
        {"step": 2, "add_joint": {"name": "catch", "type": "ball", "a": "bob", "b": "hook", "anchor": [0, 5, 0]}},
        {"step": 4, "remove_joint": "rope"},
        {"step": 5, "add": {"name": "car", "shape": {"type": "box", "half_extents": [0.5, 0.2, 0.3]},
                            "position": [0, 1, 0]}},
        {"step": 5, "add_joint": {"name": "rail", "type": "slider", "a": "car", "anchor": [0, 1, 0],
                                  "axis": [1, 0, 0], "limits": [-1, 1], "motor": {"speed": 1, "max_force": 3}}},
        {"step": 7, "remove": "car"},
        {"step": 8, "add_joint": {"name": "rail", "type": "hinge", "a": "weight", "b": "bob", "anchor": [2, 3, 0],
                                  "axis": [0, 0, 1]}},
        {"step": 9, "remove_joint": "catch"}]}))
# An add_joint refused: its body went at an earlier step.
write("fuzz_scene", "joint_action_gone_body.json", json.dumps({"steps": 4, "bodies": [
    {"name": "a", "shape": {"type": "sphere", "radius": 1}},
    {"name": "b", "shape": {"type": "sphere", "radius": 1}, "position": [3, 0, 0]}],
    "actions": [{"step": 1, "remove": "b"},
                {"step": 2, "add_joint": {"name": "j", "type": "fixed", "a": "a", "b": "b", "anchor": [1.5, 0, 0]}}]}))

# --- fuzz_hull: mode byte, count byte, then points
write("fuzz_hull", "cube", bytes([0, 8]) + b"".join(raw(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)))
write("fuzz_hull", "points_1e300", bytes([0, 5]) + raw(1e300, 0, 0, 0, 1e300, 0, 0, 0, 1e300, 1e300, 1e300, 1e300, 0, 0, 0))
# mode 1: grid 10^-k (k = 9), no offset, 4 points: three within a few grid steps, the 4th
# scaled by 1e6 (the scale byte % 4 == 0) -> a needle 1e-9 m thick and ~0.1 m long.
needle = bytes([1, 0, 9, 0, 0])
for i, p in enumerate([(0, 0, 0), (1, 0, 0), (0, 1, 0), (100, 100, 100)]):
    needle += bytes([1 if i < 3 else 0]) + bytes(c & 0xff for c in p)
write("fuzz_hull", "needle", needle)

# --- fuzz_narrowphase: flags byte (0x80 raw), shapes, rotations, positions
for mode in range(5):
    write("fuzz_narrowphase", f"boxes_mode{mode}", bytes([mode, 0]) + u16(0.6) * 3 + bytes([0]) + u16(0.4) * 3 +
          u16(0.7) + u16(0.2) + u16(0.1) + u16(0.3) + u16(0.5) * 4 + u16(0.55) * 3)
write("fuzz_narrowphase", "sphere_hull", bytes([0, 1]) + u16(0.5) + bytes([2]) + u16(0.5) + bytes([4]) +
      b"".join(u16(v) for v in (0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 0.5, 0.2, 0.9, 0.3, 0.3, 0.3, 0.7, 0.7, 0.7)))
# A cylinder (shape byte 254) against a box in every mode, and against a cylinder.
tail = u16(0.7) + u16(0.2) + u16(0.1) + u16(0.3) + u16(0.5) * 4 + u16(0.55) * 3
for mode in range(5):
    write("fuzz_narrowphase", f"cylinder_box_mode{mode}", bytes([mode, 254]) + u16(0.6) * 2 + bytes([0]) + u16(0.4) * 3 + tail)
write("fuzz_narrowphase", "cylinder_cylinder", bytes([1, 254]) + u16(0.5) * 2 + bytes([254]) + u16(0.45) * 2 + tail)
huge_box = bytes([0x80 | 0, 0]) + raw(13.117647055900639, 0.57617071270942688, 0.50029640259522512)
huge_box += bytes([0]) + raw(195.29190067006274, 1999.2532169117646, 1808.8235294117646)
huge_box += raw(float.fromhex("0x1.1f80e1b73b9fp-1"), float.fromhex("-0x1.308cc2e6e5b98p-1"),
             float.fromhex("0x1.fe82356c338bcp-4"), float.fromhex("0x1.1f82ffc2343cdp-1"))
huge_box += raw(1, 0, 0, 0)
huge_box += raw(float.fromhex("0x1.9b9b9b984cp-1"), float.fromhex("-0x1.fffffffbf4p-1"), float.fromhex("-0x1.efb3b3b3b3b3bp-1"))
huge_box += raw(float.fromhex("-0x1.7d87098eb48f4p+7"), float.fromhex("0x1.f53292975567fp+10"), float.fromhex("-0x1.c724207b31cbap+10"))
write("fuzz_narrowphase", "box_touching_huge_box", huge_box)

# --- fuzz_world: gravity, iterations, sleeping, dt, count, bodies..., steps, calls
def body(kind, static=0):
    return bytes([kind]) + u16(0.5) * 3 + bytes([static]) + u16(0.4) + u16(0.5) * 3 + bytes([1]) + \
        u16(0.6) * 4 + u16(0.5) * 6 + u16(0.5) + u16(0.3) + bytes([1])
write("fuzz_world", "stack", bytes([1, 10, 0]) + u16(0.5) + bytes([3]) + body(0, 0) + body(0, 1) + body(1) + bytes([4, 1]))
write("fuzz_world", "cylinders", bytes([1, 10, 0]) + u16(0.5) + bytes([3]) + body(0, 1) + body(254) + body(254) + bytes([4, 1]))
write("fuzz_world", "compounds", bytes([1, 10, 0]) + u16(0.5) + bytes([3]) + body(0, 1) +
      bytes([253, 1]) + (bytes([0]) + u16(0.4) * 5 + u16(0.5) * 3 + u16(0.2) * 2 + u16(0.5)) * 3 + body(1)[1:] +
      body(253) + bytes([4, 1]))
write("fuzz_world", "infinite_force", bytes([1, 10, 1]) + u16(0.5) + bytes([2]) + body(0) + body(2) +
      bytes([2, 0, 0, 0, 0]) + raw(float("inf")) + bytes([1]) + raw(1) + bytes([1]) + raw(0) + bytes([1]))
write("fuzz_world", "nan_pose", bytes([0, 4, 0]) + u16(0.5) + bytes([1]) + body(0) +
      bytes([3, 0, 0, 6]) + bytes([0]) + raw(float("nan")) * 7)

# --- fuzz_state: steps, mode (1: cut, 2: reseal), edits, (kind, offset: 3 bytes, value)...,
# cut length: 3 bytes. Kinds: 0 xor the byte with the value; 1 a double there made NaN (0),
# +inf (1), -inf (2), 1e300 (3), -1e300 (4), -0 (5), 2e15 (6), -1 (7), 4 (8), 1e-310 (9); 2 a
# u32 there made 0xFFFFFFFF (0), 0 (1), 1 (2), 1000 (3), 2^31 (4), 0xFFFFFFFE (5), 17 (6).
# The world holds every shape and joint kind; after 30 steps its stack sleeps.
def offset(n):
    return bytes([n & 0xff, (n >> 8) & 0xff, (n >> 16) & 0xff])


def edit(kind, at, value):
    return bytes([kind]) + offset(at) + bytes([value])


for steps in (0, 10, 30):
    write("fuzz_state", f"intact_{steps}", bytes([steps, 0, 0]))
write("fuzz_state", "flipped", bytes([30, 0, 1]) + edit(0, 700, 0x10))
write("fuzz_state", "flipped_resealed", bytes([30, 2, 2]) + edit(0, 700, 0x10) + edit(0, 1500, 0x80))
for name, kind, value in (("nan", 1, 0), ("inf", 1, 1), ("1e300", 1, 3), ("minus_zero", 1, 5), ("2e15", 1, 6),
                          ("u32_max", 2, 0), ("u32_1000", 2, 3), ("u32_2e31", 2, 4)):
    for at in (66, 1200, 4000, 9000):
        write("fuzz_state", f"{name}_{at}_resealed", bytes([30, 2, 1]) + edit(kind, at, value))
# Seven edits of every kind at once (its length lets the fuzzer's inputs grow to as many).
write("fuzz_state", "seven_edits_resealed", bytes([40, 2, 7]) + edit(1, 300, 0) + edit(2, 1100, 0) + edit(0, 2000, 0x40) +
      edit(1, 3000, 3) + edit(2, 5000, 3) + edit(1, 7000, 6) + edit(2, 8000, 4))
write("fuzz_state", "cut", bytes([12, 1, 0]) + offset(1000))
write("fuzz_state", "cut_resealed", bytes([12, 3, 0]) + offset(1000))
