"""What a texture sweep's CSV, BD tables, plots and page show (report.py picks it for sweeps with
`kind = "texture"`).

A texture job's result (job.py) holds the rate of the TEXTURE units (`kbit_s`, as 3dvo-enc's
"texture kbit/s"), of the H.264 streams alone (`h264_kbit_s`) and of the whole stream, and the
summary of 3dvo-metrics' texture mode: object PSNR (inside the decoded shape) and frame PSNR
(over the texture boxes), Y', Cb, Cr and the weighted YUV (docs/metrics.md). PSNRs are already
qualities in dB: BD figures use them as they are.
"""

import math
import os

_METRIC_COLUMNS = ["object_y_psnr", "object_cb_psnr", "object_cr_psnr", "object_yuv_psnr",
                   "object_pixels", "frame_y_psnr", "frame_cb_psnr", "frame_cr_psnr",
                   "frame_yuv_psnr", "frame_pixels"]
_TIME_COLUMNS = ["encode_s", "decode_s", "metrics_s"]
CSV_COLUMNS = (["sequence", "mode", "point", "setting", "frames", "cameras", "frame_rate",
                "bytes", "texture_bytes", "h264_bytes", "kbit_s", "h264_kbit_s",
                "stream_kbit_s"] + _METRIC_COLUMNS + ["frame_region"] + _TIME_COLUMNS + ["key"])

DISTORTION_NAMES = {
    "object_y_psnr": "object Y-PSNR", "object_yuv_psnr": "object YUV-PSNR",
    "frame_y_psnr": "frame Y-PSNR", "frame_yuv_psnr": "frame YUV-PSNR",
}
RATES = {"kbit_s": "texture kbit/s", "h264_kbit_s": "H.264 kbit/s"}


def _fmt(text, digits=4):
    if text in ("", None):
        return "n/a"
    return "%.*g" % (digits, float(text))


class TextureKind:
    columns = CSV_COLUMNS
    distortion_names = DISTORTION_NAMES
    default_distortion = ["object_y_psnr"]
    rates = RATES
    quality_text = "quality = the PSNR in dB (docs/metrics.md, \"Texture metrics\")"

    @staticmethod
    def row_of(result):
        job = result["job"]
        row = {
            "sequence": job["sequence"], "mode": job["mode"], "point": str(job["point"]),
            "setting": job["setting_label"], "frames": str(result["frames"]),
            "cameras": str(result["cameras"]), "frame_rate": "%.10g" % result["frame_rate"],
            "bytes": str(result["bytes"]), "texture_bytes": str(result["texture_bytes"]),
            "h264_bytes": str(result["h264_bytes"]),
            "kbit_s": "%.10g" % result["kbit_s"], "h264_kbit_s": "%.10g" % result["h264_kbit_s"],
            "stream_kbit_s": "%.10g" % result["stream_kbit_s"],
            "frame_region": result["frame_region"], "key": result["key"],
        }
        for name in _METRIC_COLUMNS:
            row[name] = result["metrics_text"].get(name, "")
        for name in _TIME_COLUMNS:
            row[name] = "%.3f" % result["time"][name]
        return row

    @staticmethod
    def quality(row, distortion):
        """The PSNR itself (infinite for a lossless point, which BD figures leave out)."""
        text = row.get(distortion, "")
        if text == "":
            return None
        value = float(text)
        return value if not math.isnan(value) else None

    @staticmethod
    def axis_label(distortion):
        return "%s [dB]" % DISTORTION_NAMES[distortion]

    @staticmethod
    def sequence_section(sweep, rows):
        out = ["| sequence | dataset | frames | cameras | frame rate | geometry |",
               "|---|---|---|---|---|---|"]
        for s in sweep.sequences:
            # Its cameras and the rate the encoder used (the sweep's frame_rate, else the
            # dataset's), from any of its rows.
            row = next((r for r in rows if r["sequence"] == s.name), None)
            out.append("| %s | `%s` | %d from %d | %s | %s | %s |" % (
                s.name, s.dataset_text, s.frame_count, s.first_frame,
                row["cameras"] if row else "n/a", row["frame_rate"] if row else "n/a",
                "`%s`" % os.path.relpath(s.pattern, sweep.root) if s.pattern
                else "the dataset's meshes"))
        prepared = [s for s in sweep.sequences if s.prepare]
        if prepared:
            out += ["", "Datasets made by the sweep's `prepare` commands when missing "
                    "({dataset} is the dataset folder, {bin} the apps' folder):", ""]
            for s in prepared:
                out.append("- %s:" % s.name)
                for command in s.prepare:
                    out.append("  `%s`" % " ".join(command))
        return out

    @staticmethod
    def points_section(sequence, rows, labels):
        out = ["| mode | setting | texture kbit/s | H.264 kbit/s | object Y-PSNR | "
               "object YUV-PSNR | frame Y-PSNR | frame YUV-PSNR | object pixels/picture |",
               "|---|---|---|---|---|---|---|---|---|"]
        region = ""
        for r in rows:
            if r["sequence"] != sequence.name:
                continue
            region = r["frame_region"]
            pictures = int(r["frames"]) * int(r["cameras"])
            out.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                labels[r["mode"]], r["setting"], _fmt(r["kbit_s"], 6), _fmt(r["h264_kbit_s"], 6),
                _fmt(r["object_y_psnr"]), _fmt(r["object_yuv_psnr"]), _fmt(r["frame_y_psnr"]),
                _fmt(r["frame_yuv_psnr"]), int(r["object_pixels"]) // max(1, pictures)))
        out.append("")
        out.append("PSNR in dB over all cameras and frames (pooled squared error); object = the "
                   "pixels inside the decoded shape; frame = %s." % (
                       "each camera's texture box" if region == "box" else "the whole frame"))
        return out
