// The camera model of docs/cameras.md in three.js terms.
//
// Dataset cameras are world → camera X_cam = R X + t with the camera looking along +z, x right,
// y down, pixel centres at integer coordinates. three.js cameras look along −z with y up, so the
// camera-to-world rotation of a dataset camera is Rᵀ · diag(1, −1, −1) and its position is the
// centre C = −Rᵀ t. The projection matrix reproduces the pixel mapping of the intrinsics exactly
// (no lens distortion: a matrix cannot express it) for a W × H viewport:
//   ndc_x = 2 (u + ½) / W − 1,  ndc_y = 1 − 2 (v + ½) / H,  u = fx X/Z + cx, v = fy Y/Z + cy.
import * as THREE from 'three';

// The camera centre −Rᵀ t (R as 3 rows).
export function cameraCentre(R, t) {
  return [0, 1, 2].map((j) => -(R[0][j] * t[0] + R[1][j] * t[1] + R[2][j] * t[2]));
}

// Sets a three.js camera's pose (position and orientation) to a dataset camera's R, t.
export function setPose(camera, R, t) {
  const c = cameraCentre(R, t);
  // Columns of the camera-to-world rotation: R's rows 0, −1, −2.
  const m = new THREE.Matrix4().set(
    R[0][0], -R[1][0], -R[2][0], c[0],
    R[0][1], -R[1][1], -R[2][1], c[1],
    R[0][2], -R[1][2], -R[2][2], c[2],
    0, 0, 0, 1);
  m.decompose(camera.position, camera.quaternion, camera.scale);
  camera.updateMatrixWorld(true);
}

// The projection matrix of intrinsics (fx, fy, cx, cy) for a W × H viewport, clipping depth to
// [near, far].
export function projectionFromIntrinsics(fx, fy, cx, cy, W, H, near, far) {
  return new THREE.Matrix4().set(
    2 * fx / W, 0, 1 - (2 * cx + 1) / W, 0,
    0, 2 * fy / H, (2 * cy + 1) / H - 1, 0,
    0, 0, -(far + near) / (far - near), -2 * far * near / (far - near),
    0, 0, -1, 0);
}

// Applies intrinsics to a three.js camera (its projection matrix and inverse).
export function setIntrinsics(camera, fx, fy, cx, cy, W, H, near, far) {
  camera.projectionMatrix.copy(projectionFromIntrinsics(fx, fy, cx, cy, W, H, near, far));
  camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
}
