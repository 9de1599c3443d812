#!/usr/bin/env python3
"""Test of 3dvo-play (ctest player_play_test): it serves the page and the decoded stream on
127.0.0.1, stops on SIGINT with exit code 0 leaving nothing behind, and refuses a damaged
stream with 3dvo-dec's error. Environment: TDVO_BIN_DIR, TDVO_PLAYER_DIR, TDVO_STREAM (a
textured conformance stream)."""

import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import unittest
import urllib.request

BIN = os.environ["TDVO_BIN_DIR"]
PLAY = os.path.join(BIN, "3dvo-play")
STREAM = os.environ["TDVO_STREAM"]


class PlayTest(unittest.TestCase):
    def start(self, stream, tmp):
        env = dict(os.environ, TMPDIR=tmp)
        return subprocess.Popen([sys.executable, PLAY, stream], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, env=env,
                                stdin=subprocess.DEVNULL)

    def test_serves_and_stops_cleanly(self):
        with tempfile.TemporaryDirectory() as tmp:
            play = self.start(STREAM, tmp)
            url = None
            for line in play.stdout:
                match = re.search(r"open (http://127\.0\.0\.1:\d+/)\S*", line)
                if match:
                    url = match.group(1)
                    break
            self.assertIsNotNone(url, play.stderr.read() if play.poll() is not None else "")
            page = urllib.request.urlopen(url, timeout=10).read().decode()
            self.assertIn("<html", page.lower())
            scene = json.loads(urllib.request.urlopen(url + "data/scene.json", timeout=10).read())
            self.assertEqual(scene["format"], "3dvo-player")
            self.assertEqual(scene["frames"]["count"], 6)
            with self.assertRaises(urllib.error.HTTPError):
                urllib.request.urlopen(url + "data/../../../etc/passwd", timeout=10)
            play.send_signal(signal.SIGINT)
            self.assertEqual(play.wait(timeout=30), 0)
            self.assertEqual(os.listdir(tmp), [])  # the decoded and exported data are gone

    def test_damaged_stream_is_refused_with_the_decoders_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            damaged = os.path.join(tmp, "cut.3dvo")
            with open(STREAM, "rb") as f:
                data = f.read()
            with open(damaged, "wb") as f:
                f.write(data[: len(data) // 2])
            work = os.path.join(tmp, "work")
            os.mkdir(work)
            play = self.start(damaged, work)
            _, err = play.communicate(timeout=60)
            self.assertEqual(play.returncode, 1)
            dec = subprocess.run([os.path.join(BIN, "3dvo-dec"), "-i", damaged],
                                 capture_output=True, text=True)
            decoder_error = dec.stderr.strip().splitlines()[-1]
            self.assertIn(decoder_error, err)
            self.assertEqual(os.listdir(work), [])


if __name__ == "__main__":
    unittest.main(verbosity=2)
