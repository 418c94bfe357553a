"""Payload codecs: the bytes are what ROS 2 CDR and protobuf readers expect, values exact."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms

from pinwind.io.messages import (
    Float64ArrayCodec,
    FrameTransformsCodec,
    JointStateCodec,
    PayloadError,
    decode_string,
    encode_string,
)


def read_cdr_multiarray(payload: bytes) -> tuple[list[tuple[str, int, int]], np.ndarray]:
    """Hand-written XCDR1 reader for std_msgs/Float64MultiArray (alignment from byte 4)."""
    assert payload[:4] == b"\x00\x01\x00\x00"  # CDR, little endian
    pos = 4

    def align(n: int) -> None:
        nonlocal pos
        pos += (-(pos - 4)) % n

    def u32() -> int:
        nonlocal pos
        align(4)
        (value,) = struct.unpack_from("<I", payload, pos)
        pos += 4
        return value

    dims = []
    for _ in range(u32()):
        length = u32()
        label = payload[pos : pos + length - 1].decode()
        pos += length
        dims.append((label, u32(), u32()))
    u32()  # data_offset
    count = u32()
    align(8)
    return dims, np.frombuffer(payload, "<f8", count, pos)


def test_float64_array_payload_is_ros2_cdr_with_labelled_dimensions():
    rng = np.random.default_rng(1)
    values = rng.normal(size=(4, 8, 3))
    codec = Float64ArrayCodec([("bearing", 8), ("axis", 3)])
    payloads = codec.encode(values)
    dims, data = read_cdr_multiarray(payloads[2].tobytes())
    assert dims == [("bearing", 8, 24), ("axis", 3, 3)]
    np.testing.assert_array_equal(data, values[2].ravel())


def test_float64_array_round_trip_keeps_signed_zero_nan_and_subnormals():
    values = np.array([[[-0.0, np.nan, 5e-324, np.inf]]])
    codec = Float64ArrayCodec([("value", 4)])
    back = codec.decode(codec.encode(values))
    np.testing.assert_array_equal(back.view(np.uint64), values.reshape(1, 4).view(np.uint64))


def test_float64_array_decode_refuses_another_layout():
    payloads = Float64ArrayCodec([("mesh", 6)]).encode(np.zeros((2, 6)))
    with pytest.raises(PayloadError, match="/meshes/normal"):
        Float64ArrayCodec([("joint", 6)]).decode(payloads, "/meshes/normal")


def test_joint_state_round_trip_and_stamp_is_the_log_time():
    rng = np.random.default_rng(2)
    names = ["carrier", "sun", "planet1"]
    ns = np.array([0, 999_999_999, 1_000_000_000, 61_250_000_000], dtype=np.uint64)
    position, velocity, effort = rng.normal(size=(3, 4, 3))
    codec = JointStateCodec(names)
    payloads = codec.encode(ns, position, velocity, effort)
    for k in range(4):
        sec, nanosec = struct.unpack_from("<iI", payloads[k].tobytes(), 4)
        assert sec * 1_000_000_000 + nanosec == int(ns[k])
    for got, want in zip(codec.decode(payloads), (position, velocity, effort), strict=True):
        np.testing.assert_array_equal(got, want)


def test_frame_transforms_parse_with_protobuf_to_the_same_stamps_and_poses():
    rng = np.random.default_rng(3)
    # Stamps whose varints have every length: 0, 1 ns, 127 ns, 128 ns, 0.3 s, 1 s, 2.1 s, 300 s
    ns = np.array(
        [0, 1, 127, 128, 300_000_000, 1_000_000_000, 2_100_000_000, 300_000_000_000], np.uint64
    )
    links = ["housing", "carrier", "sun"]
    position = rng.normal(size=(len(ns), 3, 3))
    quaternion = rng.normal(size=(len(ns), 3, 4))
    position[0, 0] = 0.0
    position[1, 1, 2] = -0.0
    codec = FrameTransformsCodec("world", links)
    payloads = codec.encode(ns, position, quaternion)
    for k, payload in enumerate(payloads):
        msg = FrameTransforms()
        msg.ParseFromString(payload)
        assert [t.child_frame_id for t in msg.transforms] == links
        for i, tf in enumerate(msg.transforms):
            assert tf.parent_frame_id == "world"
            assert tf.timestamp.seconds * 1_000_000_000 + tf.timestamp.nanos == int(ns[k])
            got = [tf.translation.x, tf.translation.y, tf.translation.z]
            np.testing.assert_array_equal(
                np.array(got).view(np.uint64), position[k, i].view(np.uint64)
            )
            rot = [tf.rotation.x, tf.rotation.y, tf.rotation.z, tf.rotation.w]
            np.testing.assert_array_equal(rot, quaternion[k, i])
    got_position, got_quaternion = codec.decode(payloads)
    np.testing.assert_array_equal(got_position.view(np.uint64), position.view(np.uint64))
    np.testing.assert_array_equal(got_quaternion, quaternion)


def test_frame_transforms_decode_reads_messages_of_other_writers():
    msg = FrameTransforms()
    tf = msg.transforms.add(parent_frame_id="world", child_frame_id="sun")
    tf.translation.x, tf.rotation.w = 0.5, 1.0
    position, quaternion = FrameTransformsCodec("world", ["sun"]).decode([msg.SerializeToString()])
    np.testing.assert_array_equal(position, [[[0.5, 0.0, 0.0]]])
    np.testing.assert_array_equal(quaternion, [[[0.0, 0.0, 0.0, 1.0]]])


def test_frame_transforms_decode_names_missing_links():
    payloads = FrameTransformsCodec("world", ["sun"]).encode(
        np.zeros(1, np.uint64), np.zeros((1, 1, 3)), np.zeros((1, 1, 4))
    )
    with pytest.raises(PayloadError, match="no transform for link.*carrier"):
        FrameTransformsCodec("world", ["sun", "carrier"]).decode(payloads, "/tf")


def test_string_payload_round_trip():
    text = '<robot name="épicycloïdal"/>'
    payload = encode_string(text)
    assert struct.unpack_from("<I", payload, 4)[0] == len(text.encode()) + 1
    assert decode_string(payload) == text
