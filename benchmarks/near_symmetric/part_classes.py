# SPDX-License-Identifier: MIT
# The classes of a box by whether the small part shows at the true pose,
# from one of part_visibility's JSON lines: "visible" (at least half of the
# part's pixels seen, and at least 20), "hidden" (fewer than 5 seen),
# "partly" (the rest); a hidden one also "hidden, told" (at least 10 pixels
# seen where the truth and its nearest rival turn differ: the part's
# absence shows) or "hidden, alike" (no depth could tell them apart).
# Shared by split.py and margins.py.


def part_classes(v):
    """The box's classes, the broad one first, then the finer one if any."""
    part, seen = v['part_px'], v['visible_px']
    kind = 'visible' if seen >= 20 and 2 * seen >= part else ('hidden' if seen < 5 else 'partly')
    kinds = [kind]
    if kind == 'hidden' and 'rival_px' in v:
        kinds.append('hidden, told' if v['rival_px'] >= 10 else 'hidden, alike')
    return kinds
