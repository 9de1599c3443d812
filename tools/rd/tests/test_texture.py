"""Texture sweeps: the sweep file's texture sequences (datasets, prepare commands, {results}),
their cache keys, and a small real sweep (object PSNR, rates, BD table, page) with the apps."""

import json
import os
import shutil
import sys
import textwrap

from tests import support
from tests.support import TempDirTestCase
from tdvo_rd.sweep import Identity, Sweep, SweepError, prepare_datasets


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(textwrap.dedent(text))
    return path


class TextureSweepTest(TempDirTestCase):
    """The sweep side, with stand-in binaries (nothing is encoded)."""

    def setUp(self):
        super().setUp()
        self.bin = os.path.join(self.tmp, "bin")
        os.makedirs(self.bin)
        for name in ("3dvo-enc", "3dvo-dec", "3dvo-metrics"):
            write(os.path.join(self.bin, name), "#!/bin/sh\n# %s\n" % name)
            os.chmod(os.path.join(self.bin, name), 0o755)
        self.make_dataset(os.path.join(self.tmp, "data", "set"))

    def make_dataset(self, folder):
        """Two cameras: one image sequence (frames 0..3), one video file; meshes per frame."""
        dataset = {
            "format": "3dvo-dataset", "version": 1, "description": "test",
            "frames": {"first": 0, "count": 4, "rate": 25.0}, "meshes": "meshes/%04d.obj",
            "cameras": [
                {"name": "a", "width": 16, "height": 16, "fx": 10, "fy": 10, "cx": 7.5,
                 "cy": 7.5, "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [0, 0, 5],
                 "images": "a/%04d.png"},
                {"name": "b", "width": 16, "height": 16, "fx": 10, "fy": 10, "cx": 7.5,
                 "cy": 7.5, "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [0, 0, 6],
                 "video": "b.avi"},
            ]}
        write(os.path.join(folder, "dataset.json"), json.dumps(dataset))
        for k in range(4):
            write(os.path.join(folder, "a", "%04d.png" % k), "image %d" % k)
            write(os.path.join(folder, "meshes", "%04d.obj" % k), "v 0 0 %d\n" % k)
        write(os.path.join(folder, "b.avi"), "video")

    def sweep(self, sequence, extra=""):
        return write(os.path.join(self.tmp, "sweeps", "t.toml"), """
            [sweep]
            kind = "texture"
            root = ".."

            [[sequence]]
            name = "set"
            frame_count = 2
            first_frame = 1
            %s

            [[mode]]
            name = "full"
            set = { TextureMode = "full" }
            settings = [ { TextureQP = 30 }, { TextureQP = 40 } ]
            %s
            """ % (sequence, extra))

    def keys(self, path):
        sweep = Sweep(path)
        sweep.use_results(os.path.join(self.tmp, "results"))
        identity = Identity(self.bin)
        return [identity.key(j) for j in sweep.jobs()]

    def test_texture_jobs_get_the_dataset_keys(self):
        path = self.sweep('dataset = "data/set"')
        jobs = Sweep(path).jobs()
        self.assertEqual(len(jobs), 2)
        config = jobs[0].config
        self.assertEqual(config["Dataset"], os.path.join(self.tmp, "data", "set"))
        self.assertNotIn("InputMeshPattern", config)     # the dataset's meshes
        self.assertEqual((config["FirstFrame"], config["FrameCount"]), ("1", "2"))
        self.assertEqual(config["TextureQP"], "30")
        self.assertEqual(jobs[0].record()["kind"], "texture")

        path = self.sweep('dataset = "data/set"\npattern = "data/set/meshes/%04d.obj"')
        self.assertIn("InputMeshPattern", Sweep(path).jobs()[0].config)

    def test_first_frame_and_rate_follow_the_dataset(self):
        # The encoder's FirstFrame is a dataset frame number (frames.first + first_frame), and
        # without frame_rate in the sweep it takes the dataset's rate: FrameRate is not set.
        name = os.path.join(self.tmp, "data", "set", "dataset.json")
        with open(name) as f:
            dataset = json.load(f)
        dataset["frames"].update(first=10, rate=30.0)
        write(name, json.dumps(dataset))
        config = Sweep(self.sweep('dataset = "data/set"')).jobs()[0].config
        self.assertEqual(config["FirstFrame"], "11")
        self.assertNotIn("FrameRate", config)
        config = Sweep(self.sweep('dataset = "data/set"\nframe_rate = 24')).jobs()[0].config
        self.assertEqual(config["FrameRate"], "24")

    def test_errors_name_the_place(self):
        cases = [
            ('pattern = "x/%d.obj"', "\\[\\[sequence\\]\\] 'set': missing key 'dataset'"),
            ('dataset = "data/set"\nprepare = ["3dvo-synth"]',
             "prepare must be an array of commands"),
        ]
        for sequence, message in cases:
            with self.subTest(message=message):
                with self.assertRaisesRegex(SweepError, message):
                    Sweep(self.sweep(sequence))
        path = self.sweep('dataset = "data/set"',
                          '[[mode]]\nname = "x"\nsettings = [ { Dataset = "y" } ]\n')
        with self.assertRaisesRegex(SweepError, "Dataset is set by the runner"):
            Sweep(path)
        path = self.sweep('dataset = "data/set"')
        with open(path) as f:
            text = f.read()
        write(path, text.replace('kind = "texture"', 'kind = "video"'))
        with self.assertRaisesRegex(SweepError, "kind must be one of geometry, texture"):
            Sweep(path)
        write(path, text.replace('kind = "texture"', ""))
        with self.assertRaisesRegex(SweepError, "'dataset' and 'prepare' are for texture"):
            Sweep(path)

    def test_keys_follow_the_frames_read_not_paths(self):
        keys = self.keys(self.sweep('dataset = "data/set"'))
        self.assertEqual(len(set(keys)), 2)
        folder = os.path.join(self.tmp, "data", "set")
        # Frame 0 and mesh 3 are not coded (first_frame 1, 2 frames): no change.
        write(os.path.join(folder, "a", "0000.png"), "edited")
        write(os.path.join(folder, "meshes", "0003.obj"), "edited")
        self.assertEqual(self.keys(self.sweep('dataset = "data/set"')), keys)
        # The description and moving the dataset change nothing.
        os.rename(folder, os.path.join(self.tmp, "data", "moved"))
        self.assertEqual(self.keys(self.sweep('dataset = "data/moved"')), keys)
        folder = os.path.join(self.tmp, "data", "moved")
        # A coded image, a coded mesh, the video or the calibration change every key.
        for name, text in (("a/0002.png", "edited"), ("meshes/0001.obj", "v 1 1 1\n"),
                           ("b.avi", "other video")):
            with self.subTest(file=name):
                original = support.read_text(os.path.join(folder, name))
                write(os.path.join(folder, name), text)
                changed = self.keys(self.sweep('dataset = "data/moved"'))
                self.assertTrue(all(a != b for a, b in zip(keys, changed)))
                write(os.path.join(folder, name), original)
        with open(os.path.join(folder, "dataset.json")) as f:
            dataset = json.load(f)
        dataset["cameras"][1]["fx"] = 11
        write(os.path.join(folder, "dataset.json"), json.dumps(dataset))
        changed = self.keys(self.sweep('dataset = "data/moved"'))
        self.assertTrue(all(a != b for a, b in zip(keys, changed)))

    def test_missing_dataset_names_the_file(self):
        path = self.sweep('dataset = "data/none"')
        with self.assertRaisesRegex(SweepError, "sequence 'set': cannot read .*none/dataset.json"):
            self.keys(path)

    def test_prepare_makes_the_dataset_under_results_once(self):
        results = os.path.join(self.tmp, "results")
        source = os.path.join(self.tmp, "data", "set")
        log = os.path.join(self.tmp, "calls")
        # A stand-in generator: copies the test dataset into {dataset} and counts its calls.
        script = write(os.path.join(self.tmp, "make.sh"),
                       "#!/bin/sh\necho x >> %s\ncp -r %s/. \"$1\"\n" % (log, source))
        os.chmod(script, 0o755)
        path = self.sweep('dataset = "{results}/data/made"\nprepare = [["%s", "{dataset}"]]'
                          % script)
        sweep = Sweep(path)
        with self.assertRaisesRegex(SweepError, "needs the results folder"):
            sweep.jobs()
        sweep.use_results(results)
        with open(os.devnull, "w") as quiet:
            self.assertEqual(prepare_datasets(sweep, self.bin, quiet), ["set"])
            self.assertEqual(prepare_datasets(sweep, self.bin, quiet), [])   # it exists now
        self.assertEqual(support.count_lines(log), 1)
        made = os.path.join(results, "data", "made")
        self.assertTrue(os.path.isfile(os.path.join(made, "dataset.json")))
        self.assertEqual(sorted(os.listdir(os.path.join(results, "data"))), ["made"])
        identity = Identity(self.bin)
        self.assertEqual(len({identity.key(j) for j in sweep.jobs()}), 2)

    def test_failed_prepare_leaves_nothing(self):
        results = os.path.join(self.tmp, "results")
        for command, message in (
                ('["sh", "-c", "echo broken >&2; exit 3"]', "exit 3.*\\n.*broken"),
                ('["true"]', "wrote no dataset.json"),
                ('["echo", "{nope}"]', "unknown placeholder")):
            with self.subTest(message=message):
                path = self.sweep('dataset = "{results}/data/made"\nprepare = [%s]' % command)
                sweep = Sweep(path)
                sweep.use_results(results)
                with open(os.devnull, "w") as quiet:
                    with self.assertRaisesRegex(SweepError, message):
                        prepare_datasets(sweep, self.bin, quiet)
                self.assertEqual(os.listdir(os.path.join(results, "data")), [])


# A prepare step: the dataset's frames.rate set to 30 (3dvo-synth writes 25).
SET_RATE_30 = ("import json, sys; d = json.load(open(sys.argv[1])); d['frames']['rate'] = 30.0; "
               "json.dump(d, open(sys.argv[1], 'w'))")


class TextureRunTest(TempDirTestCase):
    """A real texture sweep: 3dvo-synth makes a 2-camera rig; 2 modes x 3 QPs."""

    def setUp(self):
        super().setUp()
        support.require_binaries(self)
        if not os.access(os.path.join(support.bin_dir(), "3dvo-synth"), os.X_OK):
            self.skipTest("3dvo-synth is not built in %s" % support.bin_dir())
        self.results = os.path.join(self.tmp, "results")
        self.sweep = write(os.path.join(self.tmp, "texture.toml"), """
            [sweep]
            kind = "texture"
            root = "%s"
            cfg = ["cfg/d3dmc-lossless.cfg"]

            [[sequence]]
            name = "tiny"
            dataset = "{results}/data/tiny"
            prepare = [["{bin}/3dvo-synth", "-o", "{dataset}", "--Cameras=2", "--FrameCount=3",
                        "--Width=96", "--Height=64", "--NoiseSigma=2"],
                       ["%s", "-c", "%s", "{dataset}/dataset.json"]]
            frame_count = 3
            set = { GOMSize = 3, TexturePreset = "fast" }

            [[mode]]
            name = "full"
            set = { TextureMode = "full", TexturePadding = "none" }
            settings = [ { TextureQP = 24 }, { TextureQP = 32 }, { TextureQP = 40 } ]

            [[mode]]
            name = "bbox-mb128"
            label = "bbox+mb128"
            set = { TextureMode = "bbox", TexturePadding = "mb128" }
            settings = [ { TextureQP = 24 }, { TextureQP = 32 }, { TextureQP = 40 } ]

            [report]
            distortion = ["object_y_psnr", "frame_y_psnr"]
            """ % (support.REPO, sys.executable, SET_RATE_30))

    def test_sweep_rows_bd_table_and_page(self):
        page = os.path.join(self.tmp, "docs", "results-tiny.md")
        args = ["run", self.sweep, "--results", self.results, "--bin-dir", support.bin_dir(),
                "--scratch", os.path.join(self.tmp, "scratch"), "--report", page]
        out = support.run_rd(*args)
        self.assertIn("6 jobs: 6 ran, 0 cached, 0 failed", out.stdout)
        self.assertIn("preparing tiny", out.stderr)
        self.assertTrue(os.path.isfile(os.path.join(self.results, "data", "tiny",
                                                    "dataset.json")))
        self.assertEqual(os.listdir(os.path.join(self.tmp, "scratch")), [])
        rows = support.csv_rows(os.path.join(self.results, "rd.csv"))
        self.assertEqual([(r["mode"], r["setting"]) for r in rows[:4]],
                         [("full", "TextureQP=24"), ("full", "TextureQP=32"),
                          ("full", "TextureQP=40"), ("bbox-mb128", "TextureQP=24")])
        for row in rows:
            self.assertEqual((row["frames"], row["cameras"]), ("3", "2"))
            # Rates: texture units at the dataset's 30 fps (FrameRate is not set) over 3
            # frames; H.264 alone is less.
            self.assertEqual(row["frame_rate"], "30")
            self.assertAlmostEqual(float(row["kbit_s"]),
                                   int(row["texture_bytes"]) * 8 / 1000 * 30 / 3, places=6)
            self.assertLess(int(row["h264_bytes"]), int(row["texture_bytes"]))
            self.assertLess(int(row["texture_bytes"]), int(row["bytes"]))
            self.assertEqual(row["frame_region"], "box")
            self.assertGreater(int(row["object_pixels"]), 0)
        for mode in ("full", "bbox-mb128"):
            points = [r for r in rows if r["mode"] == mode]
            psnr = [float(r["object_y_psnr"]) for r in points]
            rate = [float(r["kbit_s"]) for r in points]
            self.assertEqual(psnr, sorted(psnr, reverse=True), mode)
            self.assertEqual(rate, sorted(rate, reverse=True), mode)
        # Same geometry, same shape: the object is the same pixels in both modes.
        self.assertEqual(rows[0]["object_pixels"], rows[3]["object_pixels"])
        # The full mode's box is the whole frame; bbox's is smaller.
        self.assertEqual(rows[0]["frame_pixels"], str(96 * 64 * 2 * 3))
        self.assertLess(int(rows[3]["frame_pixels"]), 96 * 64 * 2 * 3)

        with open(os.path.join(self.results, "bd.csv")) as f:
            bd = f.read()
        self.assertRegex(bd, r"tiny,object_y_psnr,full,bbox-mb128,pchip,-?\d+\.\d\d,-?\d+\.\d{3},")
        text = support.read_text(page)
        self.assertIn("### object Y-PSNR, against full", text)
        self.assertIn("![tiny, object Y-PSNR](results-tiny/tiny-object_y_psnr.svg)", text)
        self.assertIn("| tiny | `{results}/data/tiny` | 3 from 0 | 2 | 30 |", text)
        self.assertTrue(os.path.isfile(os.path.join(self.tmp, "docs", "results-tiny",
                                                    "tiny-frame_y_psnr.png")))

        # A rerun uses the cache and the prepared dataset.
        out = support.run_rd(*args)
        self.assertIn("6 jobs: 0 ran, 6 cached, 0 failed", out.stdout)
        self.assertNotIn("preparing", out.stderr)
        self.assertEqual(support.read_text(page), text)



class HullDatasetTest(TempDirTestCase):
    """tools/rd/hull_dataset.py on the uu-4cam videos (skipped without the shared data)."""

    UU = os.path.join(os.path.dirname(support.REPO), "shared", "data", "multiview", "uu-4cam")

    def test_hull_explains_the_silhouettes_and_is_deterministic(self):
        import subprocess
        import sys
        if not os.path.isdir(self.UU):
            self.skipTest("the shared data %s is absent" % self.UU)
        importer = os.path.join(support.bin_dir(), "3dvo-import")
        if not os.access(importer, os.X_OK):
            self.skipTest("3dvo-import is not built in %s" % support.bin_dir())
        uu = os.path.join(self.tmp, "uu")
        subprocess.run([importer, "-i", self.UU, "-o", uu], check=True,
                       stdout=subprocess.DEVNULL)
        script = os.path.join(support.RD_DIR, "hull_dataset.py")
        outputs = []
        for name in ("a", "b"):
            out = subprocess.run([sys.executable, script, "-i", uu, "-o",
                                  os.path.join(self.tmp, name), "--voxel", "40"],
                                 check=True, stdout=subprocess.PIPE, text=True).stdout
            outputs.append(support.read_text(os.path.join(self.tmp, name, "hull.obj")))
        self.assertEqual(outputs[0], outputs[1])
        # Every camera's silhouette is mostly covered by the hull's projection (the calibration
        # is approximate: the data's README gives IoU about 0.8 for a voxel hull).
        ious = [float(line.rsplit(" ", 1)[1]) for line in out.splitlines() if "IoU" in line]
        self.assertEqual(len(ious), 4)
        self.assertGreater(min(ious), 0.7, out)
        with open(os.path.join(self.tmp, "a", "dataset.json")) as f:
            dataset = json.load(f)
        self.assertEqual(dataset["meshes"], "hull.obj")
        self.assertTrue(all(os.path.isabs(c["video"]) for c in dataset["cameras"]))
        faces = [line for line in outputs[0].splitlines() if line.startswith("f ")]
        self.assertGreater(len(faces), 1000)


class ReconDatasetTest(TempDirTestCase):
    """tools/rd/recon_dataset.py: a dataset's cameras with a 3dvo-recon output as geometry. The
    reconstruction is stood in for by the rig's own meshes (same files 3dvo-recon writes: OBJ
    frames, goms.txt, frames.csv, report.txt); the result is coded by 3dvo-enc."""

    def setUp(self):
        super().setUp()
        for name in ("3dvo-synth", "3dvo-enc"):
            if not os.access(os.path.join(support.bin_dir(), name), os.X_OK):
                self.skipTest("%s is not built in %s" % (name, support.bin_dir()))
        import subprocess
        self.rig = os.path.join(self.tmp, "rig")
        subprocess.run([os.path.join(support.bin_dir(), "3dvo-synth"), "-o", self.rig,
                        "--Cameras=2", "--FrameCount=4", "--Width=64", "--Height=48"],
                       check=True, stdout=subprocess.DEVNULL)
        self.recon = os.path.join(self.tmp, "recon")
        os.makedirs(self.recon)
        for k in range(3):
            shutil.copyfile(os.path.join(self.rig, "meshes", "%04d.obj" % k),
                            os.path.join(self.recon, "%04d.obj" % k))
        write(os.path.join(self.recon, "goms.txt"), "# GOM list\n0 2\n2 1\n")
        write(os.path.join(self.recon, "frames.csv"),
              "frame,source,gom\n0,0,0\n1,1,0\n2,2,1\n")
        write(os.path.join(self.recon, "report.txt"), "# 3dvo-recon report\n")
        write(os.path.join(self.recon, "encode.cfg"), "InputMeshPattern : /elsewhere/%04d.obj\n")

    def run_script(self, out):
        import subprocess
        import sys
        return subprocess.run([sys.executable, os.path.join(support.RD_DIR, "recon_dataset.py"),
                               "-i", self.rig, "-r", self.recon, "-o", out],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def test_dataset_with_the_reconstruction_as_geometry(self):
        out = os.path.join(self.tmp, "out")
        done = self.run_script(out)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("3 frames, GOMs (first, count): 0,2 2,1", done.stdout)
        with open(os.path.join(out, "dataset.json")) as f:
            dataset = json.load(f)
        self.assertEqual(dataset["meshes"], "recon/%04d.obj")
        self.assertEqual(dataset["frames"]["count"], 3)
        self.assertTrue(all(os.path.isabs(c["images"]) for c in dataset["cameras"]))
        self.assertIn("meshes: 3dvo-recon, frames 0 .. 2 in 2 GOMs", dataset["description"])
        self.assertEqual(sorted(os.listdir(os.path.join(out, "recon"))),
                         ["0000.obj", "0001.obj", "0002.obj", "frames.csv", "goms.txt",
                          "report.txt"])
        # Deterministic, and a valid texture input: the encoder codes it with the GOM list.
        again = os.path.join(self.tmp, "again")
        self.assertEqual(self.run_script(again).returncode, 0)
        self.assertEqual(support.read_text(os.path.join(again, "dataset.json")),
                         support.read_text(os.path.join(out, "dataset.json")))
        import subprocess
        enc = subprocess.run([os.path.join(support.bin_dir(), "3dvo-enc"), "--Dataset=" + out,
                              "--FrameCount=3", "--GOMListFile=" + os.path.join(out, "recon",
                                                                                 "goms.txt"),
                              "--TexturePreset=ultrafast", "-o", os.path.join(self.tmp, "s.3dvo")],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.assertEqual(enc.returncode, 0, enc.stderr)
        self.assertEqual(len([l for l in enc.stdout.splitlines() if " texture " in l]), 3 * 2)

    def test_errors(self):
        write(os.path.join(self.recon, "frames.csv"), "frame,source,gom\n0,5,0\n1,6,0\n2,7,1\n")
        done = self.run_script(os.path.join(self.tmp, "a"))
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("output frame 0 comes from dataset frame 5", done.stderr)
        write(os.path.join(self.recon, "frames.csv"), "frame,source,gom\n0,0,0\n1,1,0\n2,2,1\n")
        os.remove(os.path.join(self.recon, "0002.obj"))
        done = self.run_script(os.path.join(self.tmp, "b"))
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("0002.obj: missing", done.stderr)
        write(os.path.join(self.recon, "goms.txt"), "0 2\n3 1\n")
        done = self.run_script(os.path.join(self.tmp, "c"))
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("goms.txt:2: GOM 3 1 does not follow the previous one", done.stderr)


if __name__ == "__main__":
    import unittest
    unittest.main()
