"""3dvo-rd: the rate-distortion runner of 3DVO (docs/rd.md)."""
