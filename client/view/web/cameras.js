// The three cameras: orbit (drag to turn around the track), top-down (the
// whole track from above) and chase (behind the chosen car).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class Cameras {
  constructor(camera, dom) {
    this.camera = camera;
    this.controls = new OrbitControls(camera, dom);
    this.mode = 'orbit';
    this.center = new THREE.Vector3();
    this.size = 100;
  }

  // Frames the track's bounds.
  fit(bounds) {
    const min = new THREE.Vector3(...bounds.min), max = new THREE.Vector3(...bounds.max);
    this.center.copy(min).add(max).multiplyScalar(0.5);
    this.size = Math.max(max.x - min.x, max.z - min.z, 50);
    this.camera.far = this.size * 20;
    this.camera.updateProjectionMatrix();
    this.setMode(this.mode);
  }

  setMode(mode) {
    this.mode = mode;
    this.controls.enabled = mode === 'orbit';
    const c = this.center, s = this.size;
    if (mode === 'orbit') {
      this.camera.up.set(0, 1, 0);
      this.camera.position.set(c.x + s * 0.45, c.y + s * 0.55, c.z + s * 0.75);
      this.controls.target.copy(c);
      this.controls.update();
    } else if (mode === 'top') {
      // Seen from above with x to the right and z down, as jetrace-track render draws it.
      this.camera.up.set(0, 0, -1);
      this.camera.position.set(c.x, c.y + s * 1.05, c.z);
      this.camera.lookAt(c);
    }
  }

  // Each rendered frame: the chase camera follows its car.
  follow(car) {
    if (this.mode !== 'chase' || !car || !car.seen) return;
    const p = car.group.position;
    this.camera.up.copy(car.up);
    this.camera.position.copy(p).addScaledVector(car.forward, -32).addScaledVector(car.up, 12);
    this.camera.lookAt(p.clone().addScaledVector(car.forward, 12));
  }
}
