// The 3D scene: the track mesh shaded by slope, its gates (the start line
// in red and white), and the cars as spheres with a heading arrow and a
// name; ghosts are the same, translucent. Only draws what it is given.
import * as THREE from 'three';
import { CSS2DObject } from 'three/addons/renderers/CSS2DRenderer.js';

export function carColor(slot) {
  return new THREE.Color().setHSL((slot * 0.137) % 1, 0.75, 0.55);
}

export function trackMesh(bytes) {
  const positions = new Float32Array(bytes);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.computeVertexNormals();
  const normals = geometry.getAttribute('normal');
  const colors = new Float32Array(positions.length);
  const floor = new THREE.Color(0x8d9db0), wall = new THREE.Color(0x4f5b6b);
  for (let i = 0; i < normals.count; i++) {
    const c = Math.abs(normals.getY(i)) >= 0.5 ? floor : wall;
    colors.set([c.r, c.g, c.b], i * 3);
  }
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  const material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
  return new THREE.Mesh(geometry, material);
}

function label(text, className) {
  const div = document.createElement('div');
  div.className = className;
  div.textContent = text;
  return new CSS2DObject(div);
}

export function gateObject(gate, index) {
  const v = (a) => new THREE.Vector3(a[0], a[1], a[2]);
  const c = v(gate.center), a = v(gate.across).multiplyScalar(gate.half_width_m);
  const u = v(gate.up).multiplyScalar(gate.half_height_m);
  const corners = [c.clone().sub(a).sub(u), c.clone().add(a).sub(u), c.clone().add(a).add(u), c.clone().sub(a).add(u)];
  const group = new THREE.Group();
  const start = index === 0;
  const line = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(corners),
    new THREE.LineBasicMaterial({ color: start ? 0xff3b30 : 0xffd54f }));
  group.add(line);
  const plane = new THREE.BufferGeometry().setFromPoints([corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]);
  group.add(new THREE.Mesh(plane, new THREE.MeshBasicMaterial({
    color: start ? 0xffffff : 0xffd54f, transparent: true, opacity: start ? 0.28 : 0.12, side: THREE.DoubleSide,
    depthWrite: false })));
  if (start) {
    // A red and white band across the floor of the start line.
    const cells = 12;
    for (let i = 0; i < cells; i++) {
      const p0 = corners[0].clone().lerp(corners[1], i / cells), p1 = corners[0].clone().lerp(corners[1], (i + 1) / cells);
      const geom = new THREE.BufferGeometry().setFromPoints([p0, p1, p1.clone().addScaledVector(u, 0.08),
        p0, p1.clone().addScaledVector(u, 0.08), p0.clone().addScaledVector(u, 0.08)]);
      group.add(new THREE.Mesh(geom, new THREE.MeshBasicMaterial({ color: i % 2 ? 0xffffff : 0xff3b30, side: THREE.DoubleSide })));
    }
  }
  const tag = label(start ? 'START' : String(index), 'label gate');
  tag.position.copy(c.clone().add(u));
  group.add(tag);
  return group;
}

// One car: a sphere of the car's radius, an arrow along its heading, a name.
export class CarObject {
  constructor(slot, name, radius, ghost) {
    this.slot = slot;
    this.name = name;
    this.ghost = ghost;
    this.group = new THREE.Group();
    const color = carColor(slot);
    const material = new THREE.MeshStandardMaterial({ color, roughness: 0.4, metalness: 0.1,
      transparent: ghost, opacity: ghost ? 0.35 : 1, depthWrite: !ghost });
    this.group.add(new THREE.Mesh(new THREE.SphereGeometry(radius, 24, 16), material));
    this.arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(0, 0, 0), radius * 2.4,
      ghost ? 0xc9d6e3 : 0xffffff, radius * 0.8, radius * 0.5);
    this.group.add(this.arrow);
    const tag = label(name, ghost ? 'label ghost' : 'label');
    tag.position.set(0, radius * 1.9, 0);
    this.group.add(tag);
    this.forward = new THREE.Vector3(0, 0, 1);
    this.up = new THREE.Vector3(0, 1, 0);
    this.seen = false;
  }

  // Puts the car exactly at the frame's position, turned to its heading.
  update(car) {
    this.group.position.set(car.p[0], car.p[1], car.p[2]);
    this.forward.set(car.f[0], car.f[1], car.f[2]).normalize();
    this.up.set(car.u[0], car.u[1], car.u[2]).normalize();
    const right = new THREE.Vector3().crossVectors(this.up, this.forward).normalize();
    const up = new THREE.Vector3().crossVectors(this.forward, right);
    this.group.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(right, up, this.forward));
    this.speed = car.speed;
    this.lap = car.lap;
    this.gate = car.gate;
    this.group.visible = true;
    this.seen = true;
  }
}
