"""The command line shared by the scripts that measure folders of top views
(texture_bands.py, colour_detail.py, line_profiles.py, seam_steps.py,
streak_share.py): folders as arguments, --count views of each, and a
clear message with exit status 2 for a folder without views or a view
that cannot be measured.
"""

import argparse
import glob
import json
import os
import sys


def parse_args(doc, default_count=100, labels=False):
    """Folders and --count from the command line; doc is the script's help."""
    parser = argparse.ArgumentParser(description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    what = "600 x 600 *.jpg top views with their *.json labels" if labels else \
        "600 x 600 *.jpg top views"
    parser.add_argument("folders", nargs="+", help=f"folders of {what}")
    parser.add_argument("--count", type=int, default=default_count,
                        help=f"first N views of each folder (default {default_count})")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("--count must be at least 1")
    return args


def views(folder, count, labels=False):
    """The first count *.jpg views of folder (with a *.json beside each when
    labels); exits with a message when there is none."""
    paths = sorted(glob.glob(os.path.join(folder, "*.jpg")))
    if labels:
        paths = [p for p in paths if os.path.exists(os.path.splitext(p)[0] + ".json")]
    if not paths:
        fail(f"{folder}: no *.jpg" + (" with its *.json" if labels else ""))
    return paths[:count]


def fail(message):
    print(f"{os.path.basename(sys.argv[0])}: {message}", file=sys.stderr)
    sys.exit(2)


def run(main):
    """Calls main(); a view that cannot be read or measured ends the script
    with its message and exit status 2."""
    try:
        sys.exit(main())
    except (ValueError, OSError, json.JSONDecodeError) as e:
        fail(str(e))
