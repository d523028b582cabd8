#!/usr/bin/env bash
# Regenerates the screenshots in docs/viewer.md: runs the viewer's headless
# Chromium tests (they take the screenshots) and copies what they took into
# docs/. Usage: tools/viewer_screenshots.sh [BUILD_DIR] (default: build).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
"$build/tests/viewer_test" --gtest_filter='Viewer.ChromiumDrawsTheRobots:Viewer.ChromiumShowsTheSelectedRobotsReadings:Viewer.ChromiumShowsWhatTheLoopFunctionsDrawAndTheIdOverlay'
for name in viewer viewer_inspect viewer_drawing; do
  cp "$build/tests/viewer/$name.png" "docs/$name.png"
  echo "docs/$name.png"
done
