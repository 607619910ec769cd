#!/usr/bin/python3
"""The picture of hadal-viewer in docs/viewer.md (docs/images/viewer.png): the default scenario in lockstep, stepped to
--seconds of sim time (12: the AUV about to pass over the lander), with the page open in headless Chromium.

    PYTHONPATH=build/python ROS_LOCALHOST_ONLY=1 /usr/bin/python3 tools/viewer/screenshot.py \\
        [--seconds 12] [--out docs/images/viewer.png] [--build build]
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time

import hadal

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp_browser import Browser, wait_until  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--out", default=os.path.join(ROOT, "docs/images/viewer.png"))
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    with hadal.Server("default", mode="lockstep", hadald=os.path.join(args.build, "bin/hadald")) as server, \
            tempfile.TemporaryDirectory() as profile:
        viewer = subprocess.Popen([os.path.join(args.build, "bin/hadal-viewer"), "--port", "0", "--domain-id",
                                   str(server.domain_id)], stdout=subprocess.PIPE, text=True)
        browser = Browser(profile)
        try:
            browser.open(viewer.stdout.readline().split()[2])
            wait_until(lambda: browser.evaluate("hadalViewer.seabedTriangles()") > 0, 60, "the seabed")
            with server.client("screenshot") as client:
                for _ in range(round(args.seconds * 10)):
                    client.step(50)  # 0.1 s at the default scenario's 500 Hz
                wait_until(lambda: (browser.evaluate("hadalViewer.vehiclePose('auv')") or {}).get("stamp", 0)
                           >= args.seconds - 1e-9, 30, "the page at the last step")
                time.sleep(1.0)  # the last camera frame and a plot refresh
                print(browser.screenshot(args.out))
        finally:
            browser.close()
            viewer.send_signal(signal.SIGINT)
            viewer.wait(timeout=30)


if __name__ == "__main__":
    main()
