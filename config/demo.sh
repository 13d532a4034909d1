#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on its embedded default (filled in as the pipeline lands).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/build/bin/ihf" --help
