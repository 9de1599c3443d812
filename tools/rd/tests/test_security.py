"""The Dask client's guard (issue 18, item 12): plain TCP to a scheduler on another machine is
warned about, loopback, tls:// and TLS options are not; the TLS options go together."""

import json
import os
import tempfile
import unittest

from tdvo_rd import security


class SchedulerWarningTest(unittest.TestCase):
    def test_plain_tcp_to_another_machine_is_warned_about(self):
        for address in ("tcp://10.0.0.5:8786", "tcp://scheduler.example.org:8786",
                        "10.0.0.5:8786", "tcp://0.0.0.0:8786", "tcp://[2001:db8::1]:8786"):
            warning = security.insecure_scheduler_warning(address)
            self.assertIsNotNone(warning, address)
            self.assertIn(address, warning)
            self.assertIn("run code on every worker", warning)

    def test_loopback_and_tls_are_not(self):
        for address in ("tcp://127.0.0.1:8786", "tcp://localhost:8786", "tcp://[::1]:8786",
                        "127.0.0.2:9000", "tls://10.0.0.5:8786", "inproc://x"):
            self.assertIsNone(security.insecure_scheduler_warning(address), address)
        self.assertIsNone(security.insecure_scheduler_warning("tcp://10.0.0.5:8786", tls=True))

    def test_a_scheduler_file_is_read(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "scheduler.json")
            with open(path, "w") as f:
                json.dump({"address": "tcp://192.168.1.7:8786"}, f)
            self.assertIn("192.168.1.7", security.insecure_scheduler_warning(path))
            with open(path, "w") as f:
                json.dump({"address": "tls://192.168.1.7:8786"}, f)
            self.assertIsNone(security.insecure_scheduler_warning(path))

    def test_a_scheduler_that_names_no_scheduler_is_refused(self):
        with self.assertRaisesRegex(ValueError, "--scheduler: empty address"):
            security.check_scheduler("")
        security.check_scheduler("tcp://127.0.0.1:8786")
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "scheduler.json")
            for text in ('{"address": 5}', '["tcp://127.0.0.1:8786"]', '{}', "not json"):
                with self.subTest(text=text):
                    with open(path, "w") as f:
                        f.write(text)
                    with self.assertRaisesRegex(ValueError, "scheduler.json: not a Dask "
                                                            "scheduler file"):
                        security.check_scheduler(path)
                    self.assertIsNone(security.insecure_scheduler_warning(path))
            with open(path, "w") as f:
                json.dump({"address": "tcp://127.0.0.1:8786"}, f)
            security.check_scheduler(path)

    def test_tls_options_go_together(self):
        self.assertIsNone(security.tls_options(None, None, None))
        with tempfile.TemporaryDirectory() as folder:
            files = []
            for name in ("ca.pem", "cert.pem", "key.pem"):
                files.append(os.path.join(folder, name))
                open(files[-1], "w").close()
            self.assertEqual(security.tls_options(*files), tuple(files))
            with self.assertRaises(ValueError):
                security.tls_options(files[0], None, files[2])
            with self.assertRaises(ValueError):
                security.tls_options(files[0], files[1], os.path.join(folder, "missing.pem"))


if __name__ == "__main__":
    unittest.main()
