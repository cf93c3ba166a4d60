#!/usr/bin/python3
"""The nav_msgs/Odometry messages of one topic of a ROS 1 bag as a TUM file.

    odometry_to_tum.py recorded.bag /parkslam/odom out.tum [--epoch-s 1700000000]

One line per stamp (of a frame's two messages, the later), the stamp less
--epoch-s (export-rosbag's drives start there). Prints the messages, the
distinct stamps and their rate. Read with Debian's python3-rosbag, which
decodes the messages from the definitions the bag stores.
"""
import argparse
import math
import sys

import rosbag


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bag")
    parser.add_argument("topic")
    parser.add_argument("out")
    parser.add_argument("--epoch-s", type=float, default=1.7e9)
    args = parser.parse_args()
    poses = {}
    messages = 0
    with rosbag.Bag(args.bag) as bag:
        for _, msg, _ in bag.read_messages(topics=[args.topic]):
            messages += 1
            stamp_ns = msg.header.stamp.secs * 1_000_000_000 + msg.header.stamp.nsecs
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            poses[stamp_ns] = (p.x, p.y, q.z, q.w)
    if not poses:
        sys.exit(f"{args.bag}: no message on {args.topic}")
    epoch_ns = int(round(args.epoch_s * 1e9))
    stamps = sorted(poses)
    with open(args.out, "w") as out:
        for t in stamps:
            x, y, qz, qw = poses[t]
            out.write(f"{(t - epoch_ns) / 1e9:.9f} {x:.6f} {y:.6f} 0 0 0 {qz:.10f} {qw:.10f}\n")
    span_s = (stamps[-1] - stamps[0]) / 1e9
    rate = (len(stamps) - 1) / span_s if span_s > 0 else math.nan
    print(f"{messages} messages, {len(stamps)} poses from {(stamps[0] - epoch_ns) / 1e9:.2f} s "
          f"to {(stamps[-1] - epoch_ns) / 1e9:.2f} s, {rate:.2f} Hz")


if __name__ == "__main__":
    main()
