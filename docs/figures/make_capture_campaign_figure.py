#!/usr/bin/env python
"""Regenerate the figure of docs/campaigns.md, "A capture-on-contact campaign" (about a minute):

    python docs/figures/make_capture_campaign_figure.py

capture_contact_campaign.png — the success rate (held fraction, 95 % Wilson intervals) of the
shipped gripper_servicer closing on a tumbling box's handle, against the spin rate about the
handle: 60 samples, spin uniform in [0, 0.2] rad/s, the handle's offset 2 mm (σ per axis) and the
attitude error 0.02 rad (σ per axis), 3 s runs (the same campaign as
``spacearm campaign gripper_servicer --capture-contact --samples 60 --spin 0,0.2 --offset-sigma 0.002
--attitude-sigma 0.02 --plot capture_contact_campaign.png``).
"""

import os

import spacearm
from spacearm.campaign import ApproachErrors, run_capture_campaign

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    robot = spacearm.io.load_toml(spacearm.examples.path("gripper_servicer"))
    errors = ApproachErrors(offset_sigma=0.002, attitude_sigma=0.02, spin_low=0.0, spin_high=0.2)
    result = run_capture_campaign(robot, 60, seed=0, errors=errors)
    print(result.table())
    for centre, rate, low, high, n in zip(*result.by("spin", 6)):
        print(f"spin {centre:.2f} rad/s: {rate:.2f} [{low:.2f}, {high:.2f}] of {n}")
    result.plot(os.path.join(HERE, "capture_contact_campaign.png"), parameter="spin", bins=6)


if __name__ == "__main__":
    main()
