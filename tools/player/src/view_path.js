// The page's automatic camera path: while playing, until the user moves the view, the view
// swings back and forth about the up axis through the object's centre, within the arc of
// azimuths the cameras span, so that it never shows the back no camera sees.
import * as THREE from 'three';

import { cameraCentre } from './camera_math.js';

// The dataset's up direction as tools/render/camera_path.cpp datasetUp() takes it: sh_up when
// the stream has it, else minus the mean of the cameras' y axes (row 1 of R); null without
// cameras.
export function upDirection(info) {
  if (info.up) return new THREE.Vector3().fromArray(info.up).normalize();
  if (!info.cameras.length) return null;
  const sum = new THREE.Vector3();
  for (const c of info.cameras) sum.sub(new THREE.Vector3(c.R[3], c.R[4], c.R[5]));
  return sum.length() > 1e-9 ? sum.normalize() : null;
}

// Azimuth of point p about `up` through `centre`, in the basis (e1, up × e1).
function azimuth(p, centre, up, e1) {
  const d = p.clone().sub(centre);
  const e2 = up.clone().cross(e1);
  return Math.atan2(d.dot(e2), d.dot(e1));
}

export class ViewPath {
  // cameras: the stream's cameras (R row-major, t); the arc is the smallest one holding every
  // camera's azimuth (the complement of the widest gap between neighbours), as 3dvo-render's
  // cameraArc takes it (docs/rendering.md, "Camera paths").
  constructor(cameras, centre, up) {
    this.centre = centre;
    this.up = up;
    this.e1 = new THREE.Vector3(1, 0, 0);
    if (Math.abs(this.e1.dot(up)) > 0.9) this.e1.set(0, 1, 0);
    this.e1.addScaledVector(up, -this.e1.dot(up)).normalize();
    const az = cameras.map((c) => {
      const R = [c.R.slice(0, 3), c.R.slice(3, 6), c.R.slice(6, 9)];
      return azimuth(new THREE.Vector3().fromArray(cameraCentre(R, c.t)), centre, up, this.e1);
    }).sort((a, b) => a - b);
    let gap = -1, after = 0;
    az.forEach((a, i) => {
      const next = i + 1 < az.length ? az[i + 1] : az[0] + 2 * Math.PI;
      if (next - a > gap) gap = next - a, after = (i + 1) % az.length;
    });
    this.start = az[after];
    this.span = az.length > 1 ? 2 * Math.PI - gap : 0;
    // One swing over the arc takes 4 s per 90 degrees, at least 6 s.
    this.period = Math.max(6, 2 * 4 * this.span / (Math.PI / 2));
    this.phase = null;
  }

  // Turns `view` (a three.js camera looking at `target`) to where the path is at `seconds`;
  // the first call starts the swing from the view's own azimuth. Returns the turn in radians.
  apply(view, target, seconds) {
    if (this.span <= 0) return 0;
    const now = azimuth(view.position, this.centre, this.up, this.e1);
    if (this.phase === null) {
      const into = ((now - this.start) % (2 * Math.PI) + 2 * Math.PI) % (2 * Math.PI);
      const s = Math.min(1, into / this.span);
      this.phase = Math.acos(1 - 2 * s) / (2 * Math.PI) * this.period - seconds;
    }
    const t = (seconds + this.phase) / this.period;
    const wanted = this.start + this.span * (0.5 - 0.5 * Math.cos(2 * Math.PI * t));
    let turn = wanted - now;
    turn -= 2 * Math.PI * Math.round(turn / (2 * Math.PI));
    const q = new THREE.Quaternion().setFromAxisAngle(this.up, turn);
    view.position.sub(this.centre).applyQuaternion(q).add(this.centre);
    view.quaternion.premultiply(q);
    view.updateMatrixWorld(true);
    target.sub(this.centre).applyQuaternion(q).add(this.centre);
    return turn;
  }

  // The swing restarts from wherever the view is.
  restart() { this.phase = null; }
}
