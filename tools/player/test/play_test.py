#!/usr/bin/env python3
"""Test of 3dvo-play (ctest player_play_test; docs/rendering.md, "The web player").

3dvo-play serves the player folder and one stream on 127.0.0.1: the URL it prints, the page,
the WebAssembly module and the stream with their content types, the stream read anew for every
request, Range requests (206, 416, several ranges: 200), nothing outside the folder (404 for
paths that leave it, also through symbolic links), refused streams and a player folder without
the module (exit code 1, nothing served), the folder found beside the script (a build's
player/, an installed share/3dvo/player), and SIGINT and SIGTERM ending it with exit code 0
within 2 s.

The served player folder is a temporary one: index.html and src/ copied from the build's
player folder (TDVO_PLAYER_DIR) and its wasm/ when scripts/wasm.sh has built the module; when
it has not, wasm/ holds two small dummy files (the test says so), as 3dvo-play only serves
them. One more test serves the build's own player folder, three.js included; it is skipped,
saying why, when that folder has no wasm/.

Environment: TDVO_BIN_DIR (3dvo-play), TDVO_PLAYER_DIR (the build's player folder),
TDVO_STREAMS (conformance/streams).
"""

import http.client
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

PLAY = os.path.join(os.environ["TDVO_BIN_DIR"], "3dvo-play")
BUILT_PLAYER = os.environ["TDVO_PLAYER_DIR"]
STREAMS = os.environ["TDVO_STREAMS"]
TEXTURED = os.path.join(STREAMS, "texture_bbox_mb128_g3.3dvo")
GEOMETRY_ONLY = os.path.join(STREAMS, "d3dmc_lossless_g8.3dvo")
WASM = ("tdvo_decoder.js", "tdvo_decoder.wasm")
URL = re.compile(r"open http://(127\.0\.0\.1|\[::1\]):(\d+)/\?stream=(\S+).*\n")  # a line


def read(path):
    with open(path, "rb") as f:
        return f.read()


def make_player(folder):
    """A player folder: index.html and src/ of the build's, its wasm/ or dummy files, a JSON
    file. Returns whether the module is a dummy."""
    os.makedirs(os.path.join(folder, "wasm"))
    shutil.copy(os.path.join(BUILT_PLAYER, "index.html"), folder)
    shutil.copytree(os.path.join(BUILT_PLAYER, "src"), os.path.join(folder, "src"))
    with open(os.path.join(folder, "scene.json"), "w") as f:
        f.write('{"format": "test"}\n')
    dummy = not all(os.path.isfile(os.path.join(BUILT_PLAYER, "wasm", n)) for n in WASM)
    for name in WASM:
        if dummy:
            with open(os.path.join(folder, "wasm", name), "wb") as f:
                f.write(b"\0asm\1\0\0\0" if name.endswith(".wasm") else b"// dummy\n")
        else:
            shutil.copy(os.path.join(BUILT_PLAYER, "wasm", name), os.path.join(folder, "wasm"))
    return dummy


class Play:
    """A running 3dvo-play: its address, port and the stream's URL path from the line it
    printed."""

    def __init__(self, stream, player, *args, play=PLAY):
        env = dict(os.environ)
        env.pop("TDVO_PLAYER_DIR", None)
        if player:
            env["TDVO_PLAYER_DIR"] = player
        self.process = subprocess.Popen([sys.executable, play, stream, *args],
                                        stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, env=env)
        self.out = b""
        deadline = time.monotonic() + 20
        while not URL.search(self.out.decode()):
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self.process.stdout], [], [], left)[0]:
                self.stop()
                raise AssertionError(f"3dvo-play printed no URL: {self.out.decode()!r}")
            chunk = os.read(self.process.stdout.fileno(), 4096)
            if not chunk:
                self.process.wait()
                raise AssertionError("3dvo-play ended without a URL: "
                                     + self.process.stderr.read().decode())
            self.out += chunk
        match = URL.search(self.out.decode())
        self.host = match.group(1).strip("[]")
        self.port = int(match.group(2))
        self.stream_url = "/" + match.group(3)

    def request(self, path, method="GET", headers=None, connection=None):
        c = connection or http.client.HTTPConnection(self.host, self.port, timeout=10)
        c.request(method, path, headers=headers or {})
        response = c.getresponse()
        body = response.read()
        if connection is None:
            c.close()
        return response, body

    def stop(self, signum=signal.SIGINT):
        """Sends signum; returns (exit code, seconds taken, stdout, stderr)."""
        start = time.monotonic()
        if self.process.poll() is None:
            self.process.send_signal(signum)
        out, err = self.process.communicate(timeout=10)
        return (self.process.returncode, time.monotonic() - start, (self.out + out).decode(),
                err.decode())


class PlayTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.player = os.path.join(cls.tmp.name, "player")
        cls.dummy_wasm = make_player(cls.player)
        if cls.dummy_wasm:
            print(f"note: {BUILT_PLAYER}/wasm/ does not hold the WebAssembly module "
                  "(bash scripts/wasm.sh, then cmake --build): the served wasm/ holds dummy files",
                  file=sys.stderr)
        # Outside the player folder: a file, and links to it and to its folder from inside.
        cls.secret = os.path.join(cls.tmp.name, "secret.txt")
        with open(cls.secret, "w") as f:
            f.write("not to be served\n")
        os.symlink(cls.secret, os.path.join(cls.player, "src", "secret.txt"))
        os.symlink(cls.tmp.name, os.path.join(cls.player, "outside"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def check_stops(self, play, signum):
        code, seconds, out, err = play.stop(signum)
        self.assertEqual(code, 0, err)
        self.assertLess(seconds, 2.0)
        self.assertNotIn("Traceback", err)
        self.assertTrue(out.rstrip().endswith("3dvo-play: stopped"), out)
        with self.assertRaises(ConnectionRefusedError):  # the socket is closed
            socket.create_connection((play.host, play.port), timeout=2).close()
        return err

    def test_serves_the_page_the_module_and_the_stream(self):
        for stream in (TEXTURED, GEOMETRY_ONLY):
            with self.subTest(stream=os.path.basename(stream)):
                play = Play(stream, self.player)
                name = os.path.basename(stream)
                self.assertIn(f"3dvo-play: open http://127.0.0.1:{play.port}/?stream=stream/"
                              f"{name}   (Ctrl-C stops)\n", play.out.decode())
                response, body = play.request("/")
                self.assertEqual(response.status, 200)
                self.assertEqual(body, read(os.path.join(self.player, "index.html")))
                self.assertEqual(response.getheader("Content-Type"), "text/html; charset=utf-8")
                for file, kind in (("wasm/tdvo_decoder.wasm", "application/wasm"),
                                   ("wasm/tdvo_decoder.js", "text/javascript; charset=utf-8"),
                                   ("src/player.js", "text/javascript; charset=utf-8"),
                                   ("scene.json", "application/json")):
                    response, body = play.request("/" + file)
                    self.assertEqual((response.status, response.getheader("Content-Type")),
                                     (200, kind), file)
                    self.assertEqual(body, read(os.path.join(self.player, file)), file)
                    self.assertEqual(int(response.getheader("Content-Length")), len(body))
                data = read(stream)
                response, body = play.request(f"/stream/{name}")
                self.assertEqual(response.status, 200)
                self.assertEqual(body, data)
                self.assertEqual(response.getheader("Content-Length"), str(len(data)))
                self.assertEqual(response.getheader("Cache-Control"), "no-cache")
                self.assertEqual(response.getheader("Accept-Ranges"), "bytes")
                response, body = play.request(f"/stream/{name}", method="HEAD")
                self.assertEqual((response.status, body), (200, b""))
                self.assertEqual(response.getheader("Content-Length"), str(len(data)))
                # Nothing logged per request.
                self.assertEqual(self.check_stops(play, signal.SIGINT), "")

    def test_range_requests(self):
        play = Play(TEXTURED, self.player)
        data, size = read(TEXTURED), os.path.getsize(TEXTURED)
        path = play.stream_url
        # One keep-alive connection for all of them, as a browser would.
        c = http.client.HTTPConnection("127.0.0.1", play.port, timeout=10)
        for asked, first, last in (("bytes=10-99", 10, 99), ("bytes=0-0", 0, 0),
                                   ("bytes=-16", size - 16, size - 1),
                                   ("bytes=100-", 100, size - 1),
                                   ("bytes=-999999999", 0, size - 1),
                                   (f"bytes={size - 3}-{size + 1000}", size - 3, size - 1)):
            response, body = play.request(path, headers={"Range": asked}, connection=c)
            self.assertEqual(response.status, 206, asked)
            self.assertEqual(response.getheader("Content-Range"), f"bytes {first}-{last}/{size}")
            self.assertEqual(response.getheader("Content-Length"), str(last - first + 1))
            self.assertEqual(body, data[first:last + 1], asked)
        for asked in (f"bytes={size}-", f"bytes={size + 5}-{size + 9}", "bytes=-0"):
            response, body = play.request(path, headers={"Range": asked}, connection=c)
            self.assertEqual(response.status, 416, asked)
            self.assertEqual(response.getheader("Content-Range"), f"bytes */{size}")
        # Positions of thousands of digits are past any file (Python's int() refuses them).
        huge = "9" * 5000
        for asked, status in ((f"bytes={huge}-", 416), (f"bytes=0-{huge}", 206),
                              (f"bytes=-{huge}", 206)):
            response, body = play.request(path, headers={"Range": asked}, connection=c)
            self.assertEqual(response.status, status, asked[:20])
            if status == 206:
                self.assertEqual(body, data)
        # Several ranges, or a malformed or reversed one: the whole stream.
        for asked in ("bytes=0-9,20-29", "bytes=9-0", "lines=1-2", "bytes=x-y"):
            response, body = play.request(path, headers={"Range": asked}, connection=c)
            self.assertEqual((response.status, body), (200, data), asked)
        # If-Range with another version's ETag: the whole stream.
        response, _ = play.request(path, connection=c)
        etag = response.getheader("ETag")
        response, body = play.request(path, headers={"Range": "bytes=0-3", "If-Range": etag},
                                      connection=c)
        self.assertEqual((response.status, body), (206, b"3DVO"))
        response, body = play.request(path, headers={"Range": "bytes=0-3", "If-Range": '"x"'},
                                      connection=c)
        self.assertEqual((response.status, body), (200, data))
        c.close()
        err = self.check_stops(play, signal.SIGTERM)
        self.assertEqual(len(err.splitlines()), 4, err)  # one line per 416
        self.assertIn("416", err)

    def test_the_stream_is_read_for_every_request(self):
        with tempfile.TemporaryDirectory() as tmp:
            stream = os.path.join(tmp, "growing.3dvo")
            shutil.copy(TEXTURED, stream)
            play = Play(stream, self.player)
            self.assertEqual(play.request(play.stream_url)[1], read(TEXTURED))
            with open(stream, "ab") as f:
                f.write(b"more")
            response, body = play.request(play.stream_url, headers={"Range": "bytes=-4"})
            self.assertEqual((response.status, body), (206, b"more"))
            self.assertEqual(play.request(play.stream_url)[1], read(TEXTURED) + b"more")
            self.check_stops(play, signal.SIGINT)

    def test_a_stream_replaced_by_a_fifo_is_an_error_not_a_hang(self):
        with tempfile.TemporaryDirectory() as tmp:
            stream = os.path.join(tmp, "s.3dvo")
            shutil.copy(TEXTURED, stream)
            play = Play(stream, self.player)
            os.remove(stream)
            os.mkfifo(stream)
            start = time.monotonic()
            response, _ = play.request(play.stream_url)
            self.assertEqual(response.status, 500)
            self.assertLess(time.monotonic() - start, 5)
            err = self.check_stops(play, signal.SIGINT)
            self.assertIn("not a regular file", err)

    def test_connections_are_bounded(self):
        # MAX_CONNECTIONS silent connections hold every slot; one more is answered 503 and
        # closed; once they are gone, requests are served again.
        play = Play(TEXTURED, self.player)
        silent = [socket.create_connection(("127.0.0.1", play.port)) for _ in range(64)]
        try:
            time.sleep(0.5)
            extra = socket.create_connection(("127.0.0.1", play.port), timeout=10)
            extra.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
            answer = b""
            while chunk := extra.recv(4096):
                answer += chunk
            extra.close()
            self.assertTrue(answer.startswith(b"HTTP/1.1 503"), answer)
        finally:
            for s in silent:
                s.close()
        deadline = time.monotonic() + 10
        while True:
            try:
                if play.request("/")[0].status == 200:
                    break
            except (ConnectionError, http.client.HTTPException):
                pass
            self.assertLess(time.monotonic(), deadline, "not served again")
            time.sleep(0.1)
        self.check_stops(play, signal.SIGTERM)

    def test_nothing_outside_the_folder_is_served(self):
        play = Play(TEXTURED, self.player)
        name = os.path.basename(TEXTURED)
        paths = ["/../secret.txt", "/%2e%2e/secret.txt", "/src/../../secret.txt",
                 "/src/%2E%2E/%2E%2E/secret.txt", "/..%2fsecret.txt", "/src/secret.txt",
                 "/outside/secret.txt", "//etc/passwd",
                 "/src/..%5C..%5Csecret.txt", f"/stream/../stream/{name}", "/stream/other.3dvo",
                 f"/stream/{name}/x", "/wasm/", "/src", "/index.html%00.js",
                 "/" + os.path.relpath(self.secret, "/")]
        for path in paths:
            response, body = play.request(path)
            self.assertEqual(response.status, 404, path)
            self.assertNotIn(b"not to be served", body)
        err = self.check_stops(play, signal.SIGINT)
        self.assertEqual(len(err.splitlines()), len(paths), err)  # one line per error

    def test_refused_streams(self):
        with tempfile.TemporaryDirectory() as tmp:
            not_3dvo = os.path.join(tmp, "picture.3dvo")
            with open(not_3dvo, "wb") as f:
                f.write(b"\x89PNG\r\n\x1a\n" + read(TEXTURED)[8:])
            empty = os.path.join(tmp, "empty.3dvo")
            open(empty, "wb").close()
            cases = [(os.path.join(tmp, "missing.3dvo"), "no such file"),
                     (tmp, "not a regular file"), (not_3dvo, "not a 3DVO stream"),
                     (empty, "not a 3DVO stream")]
            if os.geteuid() != 0:  # root reads any file
                unreadable = os.path.join(tmp, "unreadable.3dvo")
                shutil.copy(TEXTURED, unreadable)
                os.chmod(unreadable, 0)
                cases.append((unreadable, "cannot be read"))
            for stream, reason in cases:
                with self.subTest(stream=stream):
                    result = subprocess.run([sys.executable, PLAY, stream], capture_output=True,
                                            text=True, timeout=20, stdin=subprocess.DEVNULL,
                                            env=dict(os.environ, TDVO_PLAYER_DIR=self.player))
                    self.assertEqual(result.returncode, 1)
                    self.assertEqual(result.stdout, "")  # no URL: nothing served
                    self.assertEqual(result.stderr, f"3dvo-play: error: {stream}: {reason}"
                                     + (' (it does not start with "3DVO")\n'
                                        if "3DVO" in reason else "\n"))

    def test_a_player_folder_without_the_module_is_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            player = os.path.join(tmp, "player")
            make_player(player)
            os.remove(os.path.join(player, "wasm", "tdvo_decoder.wasm"))
            result = subprocess.run([sys.executable, PLAY, TEXTURED], capture_output=True,
                                    text=True, timeout=20, stdin=subprocess.DEVNULL,
                                    env=dict(os.environ, TDVO_PLAYER_DIR=player))
            self.assertEqual((result.returncode, result.stdout), (1, ""))
            self.assertIn(f"{player}/wasm/tdvo_decoder.wasm not found", result.stderr)
            self.assertIn("bash scripts/wasm.sh", result.stderr)

    def test_the_player_folder_is_found_beside_the_script(self):
        with tempfile.TemporaryDirectory() as tmp:
            for layout in ("player", "share/3dvo/player"):
                with self.subTest(layout=layout):
                    root = os.path.join(tmp, layout.split("/")[0] + "-tree")
                    os.makedirs(os.path.join(root, "bin"))
                    play_copy = os.path.join(root, "bin", "3dvo-play")
                    shutil.copy(PLAY, play_copy)
                    make_player(os.path.join(root, layout))
                    play = Play(TEXTURED, None, play=play_copy)
                    response, body = play.request("/")
                    self.assertEqual(body, read(os.path.join(root, layout, "index.html")))
                    self.check_stops(play, signal.SIGTERM)

    def test_port_and_signals_during_a_connection(self):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        for signum in (signal.SIGINT, signal.SIGTERM):
            with self.subTest(signal=signum.name):
                play = Play(TEXTURED, self.player, "--port", str(port))
                self.assertEqual(play.port, port)
                # An open keep-alive connection does not hold it up.
                c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
                self.assertEqual(play.request("/", connection=c)[0].status, 200)
                self.check_stops(play, signum)
                c.close()
        taken = socket.socket()
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        try:
            result = subprocess.run([sys.executable, PLAY, TEXTURED, "--port",
                                     str(taken.getsockname()[1])], capture_output=True,
                                    text=True, timeout=20,
                                    env=dict(os.environ, TDVO_PLAYER_DIR=self.player))
            self.assertEqual((result.returncode, result.stdout), (1, ""))
            self.assertIn("cannot listen on 127.0.0.1", result.stderr)
        finally:
            taken.close()

    def test_host(self):
        play = Play(TEXTURED, self.player, "--host", "localhost")  # loopback: no warning
        self.assertEqual(play.request("/")[0].status, 200)
        self.assertEqual(self.check_stops(play, signal.SIGINT), "")
        result = subprocess.run([sys.executable, PLAY, TEXTURED, "--host", "no-such-host.invalid"],
                                capture_output=True, text=True, timeout=30,
                                env=dict(os.environ, TDVO_PLAYER_DIR=self.player))
        self.assertEqual((result.returncode, result.stdout), (1, ""))
        self.assertIn("3dvo-play: error: --host no-such-host.invalid: ", result.stderr)

    def test_help(self):
        result = subprocess.run([sys.executable, PLAY, "--help"], capture_output=True, text=True,
                                timeout=20)
        self.assertEqual(result.returncode, 0)
        for words in ("--port", "--host", "--open", "Range", "416", "404", "scripts/wasm.sh",
                      "TDVO_PLAYER_DIR", "share/3dvo/player", "SIGTERM", "loopback"):
            self.assertIn(words, result.stdout)

    def test_version(self):
        # Every app takes --version (docs/user-guide.md); the build fills in the release.
        result = subprocess.run([sys.executable, PLAY, "--version"], capture_output=True,
                                text=True, timeout=20)
        self.assertEqual((result.returncode, result.stderr), (0, ""))
        self.assertRegex(result.stdout, r"^3dvo-play \(3DVO [0-9]+\.[0-9]+\.[0-9]+\)\n  Python ")

    def test_the_builds_player_folder(self):
        if not all(os.path.isfile(os.path.join(BUILT_PLAYER, "wasm", n)) for n in WASM):
            self.skipTest(f"{BUILT_PLAYER}/wasm/ does not hold the WebAssembly module "
                          "(bash scripts/wasm.sh, then cmake --build)")
        play = Play(GEOMETRY_ONLY, BUILT_PLAYER)
        for file in ("index.html", "wasm/tdvo_decoder.js", "wasm/tdvo_decoder.wasm",
                     "node_modules/three/build/three.module.js",
                     "node_modules/three/examples/jsm/controls/OrbitControls.js"):
            response, body = play.request("/" + file)
            self.assertEqual((response.status, body), (200, read(os.path.join(BUILT_PLAYER, file))))
        self.check_stops(play, signal.SIGINT)


if __name__ == "__main__":
    unittest.main(verbosity=2)
