#!/usr/bin/env bash
# Installs the Debian packages parkslam needs, and only those that are missing.
# Safe to run again: with everything present it installs nothing.
# --with-browser also installs Chromium, which the report's browser test
# needs (scripts/test.sh asks for it; the demo does not); --with-fuzzer
# installs Clang and its libFuzzer runtime (scripts/fuzz.sh); --with-format
# installs clang-format (the format_check test, scripts/check_format.sh);
# --with-ros installs ROS 1's libraries and tools for the node (ros/,
# docs/ros.md: -DPARKSLAM_ROS=ON) and its test (rosmaster, roslaunch,
# rosbag play and record, rosservice).
# librosbag-storage-dev (ROS 1 bags, for import-rosbag) brings Boost and a
# few ROS libraries with it; ccache makes rebuilds and CI's fresh clones
# fast (scripts/compiler_cache.sh).
set -euo pipefail

packages=(
  build-essential cmake ccache
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libceres-dev libopencv-dev libopencv-contrib-dev libapriltag-dev
  fonts-dejavu-core fonts-dejavu-extra fonts-liberation fonts-freefont-ttf fonts-urw-base35
  fonts-noto-core fonts-open-sans fonts-cantarell fonts-roboto-unhinted
  libgtest-dev libgmock-dev libbenchmark-dev
  librosbag-storage-dev
)
for option in "$@"; do
  case "$option" in
    --with-browser) packages+=(chromium) ;;
    --with-fuzzer) packages+=(clang libclang-rt-dev) ;;
    --with-format) packages+=(clang-format) ;;
    --with-ros)
      packages+=(libroscpp-dev libtf2-ros-dev libtopic-tools-dev libnav-msgs-dev libsensor-msgs-dev
                 libstd-msgs-dev libgeometry-msgs-dev
                 libvisualization-msgs-dev libstd-srvs-dev python3-rosmaster python3-roslaunch
                 python3-rosbag python3-rosparam python3-rostopic python3-rosservice python3-std-srvs
                 python3-std-msgs rospack-tools) ;;
    *) echo "install_deps.sh: unknown option '$option' (--with-browser, --with-fuzzer, --with-format, --with-ros)" >&2; exit 2 ;;
  esac
done

exec "$(dirname "$0")/apt_install_missing.sh" install_deps "${packages[@]}"
