"""The independent ROS 2 readers and writers, run by the tests in the clients' own venv.

    python ros2_clients.py read FILE...     every message of each a2b file, as rosbags'
                                            AnyReader and mcap + mcap-ros2-support decode it
    python ros2_clients.py write DIR        a bag written by rosbags' Writer (MCAP storage),
                                            with the values it holds

Prints JSON. Doubles are written with ``float.hex``, so the test compares them bit for bit.
Not a test module: it imports rosbags and mcap_ros2, which only that venv has.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def pose_of(msg) -> list:
    """The 7 doubles of a Pose or a Transform, in ROS order: x y z, then qx qy qz qw."""
    position = getattr(msg, "position", None) or msg.translation
    orientation = getattr(msg, "orientation", None) or msg.rotation
    values = [position.x, position.y, position.z]
    values += [orientation.x, orientation.y, orientation.z, orientation.w]
    return [float(v).hex() for v in values]


def stamp_of(header) -> list:
    return [int(header.stamp.sec), int(header.stamp.nanosec), header.frame_id]


def content(msg, type_name: str):
    """The values of a message of the types a2b writes or reads, as plain JSON."""
    if type_name.endswith("PoseStamped"):
        return [stamp_of(msg.header), pose_of(msg.pose)]
    if type_name.endswith("TFMessage"):
        return [
            [stamp_of(t.header), t.child_frame_id, pose_of(t.transform)] for t in msg.transforms
        ]
    if type_name.endswith("Path"):
        return [stamp_of(msg.header), [content(p, "PoseStamped") for p in msg.poses]]
    if type_name.endswith("Odometry"):
        return [stamp_of(msg.header), msg.child_frame_id, pose_of(msg.pose.pose)]
    raise ValueError(type_name)


def read(path: str) -> dict:
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader

    out: dict = {"rosbags": [], "mcap_ros2": [], "same_bytes": [], "qos": {}}
    with AnyReader([Path(path)]) as reader:
        for connection in reader.connections:
            out["qos"][connection.topic] = [
                [q.history.value, q.depth, q.reliability.value, q.durability.value]
                for q in connection.ext.offered_qos_profiles
            ]
        for connection, log_time, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            out["rosbags"].append([connection.topic, log_time, content(msg, connection.msgtype)])
            again = reader.typestore.serialize_cdr(msg, connection.msgtype)
            out["same_bytes"].append(bytes(again) == bytes(raw))
    with open(path, "rb") as f:
        decoded = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, channel, message, msg in decoded.iter_decoded_messages(log_time_order=True):
            out["mcap_ros2"].append([channel.topic, message.log_time, content(msg, schema.name)])
    return out


def write(directory: str) -> dict:
    """A bag of the message types a2b reads, with frame ids of several lengths (so that the
    padding differs from message to message) and a /tf of two child frames."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    Time, Header = types["builtin_interfaces/msg/Time"], types["std_msgs/msg/Header"]
    Point, Quaternion = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Quaternion"]
    Vector3, Pose = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Pose"]
    import numpy as np

    rng = np.random.default_rng(5)
    expected: dict = {"pose": [], "tf": [], "odom": [], "plan": []}

    def pose(k):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        p = rng.normal(size=3)
        return (
            Pose(position=Point(x=p[0], y=p[1], z=p[2]),
                 orientation=Quaternion(x=q[1], y=q[2], z=q[3], w=q[0])),
            [float(v).hex() for v in (*p, *q[1:], q[0])],
        )  # fmt: skip

    def header(k, frame):
        return Header(stamp=Time(sec=100 + k, nanosec=250_000_000 * (k % 4)), frame_id=frame)

    names = {
        "/pose": "geometry_msgs/msg/PoseStamped",
        "/tf": "tf2_msgs/msg/TFMessage",
        "/odom": "nav_msgs/msg/Odometry",
        "/plan": "nav_msgs/msg/Path",
    }
    with Writer(Path(directory), version=8, storage_plugin=StoragePlugin.MCAP) as writer:
        connections = {
            topic: writer.add_connection(topic, name, typestore=store)
            for topic, name in names.items()
        }

        def put(topic, k, msg):
            data = store.serialize_cdr(msg, names[topic])
            writer.write(connections[topic], (100 + k) * 10**9, data)

        for k in range(7):
            frame = "m" * (k + 1)  # lengths 1 … 7: every padding
            p, values = pose(k)
            put("/pose", k, types[names["/pose"]](header=header(k, frame), pose=p))
            expected["pose"].append([100 + k, 250_000_000 * (k % 4), values])
            transforms = []
            for child in ("base", "camera_link"):
                p, values = pose(k)
                transform = types["geometry_msgs/msg/Transform"](
                    translation=Vector3(x=p.position.x, y=p.position.y, z=p.position.z),
                    rotation=p.orientation,
                )
                transforms.append(
                    types["geometry_msgs/msg/TransformStamped"](
                        header=header(k, frame), child_frame_id=child, transform=transform
                    )
                )
                if child == "camera_link":
                    expected["tf"].append([100 + k, 250_000_000 * (k % 4), values])
            put("/tf", k, types[names["/tf"]](transforms=transforms))
            p, values = pose(k)
            covariance = types["geometry_msgs/msg/PoseWithCovariance"](
                pose=p, covariance=np.arange(36, dtype=float)
            )
            twist = types["geometry_msgs/msg/TwistWithCovariance"](
                twist=types["geometry_msgs/msg/Twist"](
                    linear=Vector3(x=1.0, y=2.0, z=3.0), angular=Vector3(x=4.0, y=5.0, z=6.0)
                ),
                covariance=np.zeros(36),
            )
            odometry = types[names["/odom"]](
                header=header(k, frame), child_frame_id="b" * k, pose=covariance, twist=twist
            )
            put("/odom", k, odometry)
            expected["odom"].append([100 + k, 250_000_000 * (k % 4), values])
        for plan in range(2):  # the last Path is the one read
            poses, values = [], []
            for k in range(5):
                p, v = pose(k)
                frame = "f" * (k + plan + 1)
                poses.append(
                    types["geometry_msgs/msg/PoseStamped"](header=header(k, frame), pose=p)
                )
                values.append([100 + k, 250_000_000 * (k % 4), v])
            put("/plan", 10 + plan, types[names["/plan"]](header=header(0, "map"), poses=poses))
            expected["plan"] = values
    expected["file"] = str(next(Path(directory).glob("*.mcap")))
    return expected


if __name__ == "__main__":
    command, *paths = sys.argv[1:]
    if command == "read":
        json.dump({path: read(path) for path in paths}, sys.stdout)
    else:
        json.dump(write(paths[0]), sys.stdout)
