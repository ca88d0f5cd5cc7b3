// The legdsl run player: draws a recorded run with three.js, all data inline.
// World frame as in legdsl: x forward, y left, z up. Poses are stored per frame
// and body as (px, py, pz, qx, qy, qz, qw); the player interpolates between
// frames (lerp / slerp), so slow motion stays smooth.

import * as THREE from "three"; // the vendored three.js, mapped to a blob URL by the page

const data = JSON.parse(document.getElementById("legdsl-data").textContent);

// ------------------------------------------------------------------ data
function bytes(b64) {
  const bin = atob(b64);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
  return out.buffer;
}
const f32 = (b64) => new Float32Array(bytes(b64));
const times = f32(data.times);
const poses = f32(data.poses); // frames x bodies x 7
const contactPos = f32(data.contactPositions); // frames x contacts x 3
const forces = f32(data.forces); // frames x contacts x 3
const com = f32(data.com); // frames x 3
// frames: how far the camera's target rises above lookHeight to keep the creature in frame
const lift = data.cameraLift ? f32(data.cameraLift) : new Float32Array(times.length);
const speed = f32(data.speed);
const speedCommand = f32(data.speedCommand);
const state = new Int16Array(bytes(data.state));
const nFrames = times.length;
const nBodies = data.bodies.length;
const nContacts = data.contacts.length;
const duration = nFrames > 1 ? times[nFrames - 1] : 0;

// ------------------------------------------------------------------ scene
const view = document.getElementById("view");
const message = document.getElementById("message");

// Without WebGL (none offered, or its context lost) the same run is drawn on a 2D canvas, seen
// from the side (x to the right, z up), with a note saying so: never a blank page.
const flat = { canvas: null, on: false };
const bodyMeshes2d = data.bodies.map((b) => ({
  positions: f32(b.mesh.positions),
  indices: new Uint32Array(bytes(b.mesh.indices)),
  color: b.color,
}));
// The height of a slope's plane at x (0 without one: steps and boxes stand on the floor).
function slopeZ(x) {
  const s = data.ground.terrain.find((k) => k.kind === "slope");
  return s ? x * Math.tan(s.angle) : 0;
}

// The ground's height under (x, y), as legdsl.sim.contact models it (motion.terrain_height).
function groundHeight(x, y) {
  let z = 0;
  for (const k of data.ground.terrain) {
    if (k.kind === "slope") return x * Math.tan(k.angle);
    if (k.kind === "step" && x >= k.x) z = Math.max(z, k.height);
    if (k.kind === "box" && x >= k.x0 && x <= k.x1 && y >= k.y0 && y <= k.y1) z = Math.max(z, k.height);
  }
  return z;
}

function draw2d(t, note) {
  if (!flat.canvas) {
    flat.canvas = document.createElement("canvas");
    flat.canvas.id = "flat-view";
    Object.assign(flat.canvas.style, { position: "absolute", inset: "0", width: "100%", height: "100%" });
    view.appendChild(flat.canvas);
  }
  flat.on = true;
  flat.canvas.style.display = "block";
  message.textContent = note;
  const w = view.clientWidth || 800, h = view.clientHeight || 500;
  flat.canvas.width = w; flat.canvas.height = h;
  const g = flat.canvas.getContext("2d");
  const f = frameAt(t)[0];
  const scale = h / (2.4 * data.size);
  const cx = com[3 * f], cz = data.lookHeight + lift[f] + slopeZ(cx);
  const X = (x) => w / 2 + (x - cx) * scale, Z = (z) => h / 2 - (z - cz) * scale;
  g.fillStyle = "#eef0f3"; g.fillRect(0, 0, w, h);
  const slope2d = data.ground.terrain.find((k) => k.kind === "slope");
  const groundZ = (x) => {
    if (slope2d) return x * Math.tan(slope2d.angle);
    let z = 0;
    for (const k of data.ground.terrain) {
      if (k.kind === "step" && x >= k.x) z = Math.max(z, k.height);
      if (k.kind === "box" && x >= k.x0 && x <= k.x1) z = Math.max(z, k.height);
    }
    return z;
  };
  g.fillStyle = "#d9d9d6"; g.strokeStyle = "#98988f";
  g.beginPath(); g.moveTo(0, h);
  for (let px = 0; px <= w; px += 2) g.lineTo(px, Z(groundZ(cx + (px - w / 2) / scale)));
  g.lineTo(w, h); g.closePath(); g.fill(); g.stroke();
  // Triangles of every link in world coordinates, far side (+y) first.
  const tris = [];
  const q = new THREE.Quaternion(), v = new THREE.Vector3();
  for (let b = 0; b < nBodies; b++) {
    const i = (f * nBodies + b) * 7, m = bodyMeshes2d[b];
    q.set(poses[i + 3], poses[i + 4], poses[i + 5], poses[i + 6]);
    const world = [];
    for (let k = 0; k < m.positions.length; k += 3) {
      v.set(m.positions[k], m.positions[k + 1], m.positions[k + 2]).applyQuaternion(q);
      world.push([v.x + poses[i], v.y + poses[i + 1], v.z + poses[i + 2]]);
    }
    for (let k = 0; k < m.indices.length; k += 3) {
      const [a, bb, c] = [world[m.indices[k]], world[m.indices[k + 1]], world[m.indices[k + 2]]];
      tris.push({ depth: a[1] + bb[1] + c[1], pts: [a, bb, c], color: m.color });
    }
  }
  tris.sort((p, r) => r.depth - p.depth);
  for (const tri of tris) {
    g.fillStyle = g.strokeStyle = tri.color;
    g.beginPath();
    tri.pts.forEach(([x, , z], k) => (k ? g.lineTo(X(x), Z(z)) : g.moveTo(X(x), Z(z))));
    g.closePath(); g.fill(); g.stroke();
  }
}

let renderer;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
} catch (err) {
  draw2d(0, "This browser offers no WebGL: the run's first frame is drawn flat, from the side.");
  throw err;
}
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFSoftShadowMap;
view.appendChild(renderer.domElement);
let contextLost = false;
renderer.domElement.addEventListener("webglcontextlost", (e) => {
  e.preventDefault(); // allow it to be restored
  contextLost = true;
  draw2d(time, "WebGL stopped working (its context was lost): drawn flat, from the side, until it is back.");
});
renderer.domElement.addEventListener("webglcontextrestored", () => {
  contextLost = false;
  flat.on = false;
  if (flat.canvas) flat.canvas.style.display = "none";
  message.textContent = "";
  requestRender();
});

const scene = new THREE.Scene();
scene.background = new THREE.Color(0xeef0f3);
scene.fog = new THREE.Fog(0xeef0f3, 1.5 * data.distance, 4.5 * data.distance);
// near and far follow the creature's size: 5 cm would cut a 0.7 mm mite, 500 m hide a giant's
// ground, and 500 m seen from half a millimetre left the depth buffer no precision for a mite
const camera = new THREE.PerspectiveCamera(35, 1, Math.min(0.05, data.distance / 20), Math.max(Math.min(500, 5000 * data.distance), 50 * data.distance));
camera.up.set(0, 0, 1);

scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 1.9));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.castShadow = true;
sun.shadow.mapSize.set(1024, 1024);
sun.shadow.bias = -0.0005; // no shadow acne on flat faces lit at a grazing angle
sun.shadow.normalBias = 0.01 * data.size;
const shadowBox = 1.5 * data.size;
// the shadow camera's depth range follows the size too: the bias is a share of it, and 10 m of
// it pushed a 0.2 mm mite's shadow off the ground
Object.assign(sun.shadow.camera, { left: -shadowBox, right: shadowBox, top: shadowBox, bottom: -shadowBox, near: Math.min(0.1, data.size), far: 20 * data.size + Math.min(10, 20 * data.size) });
scene.add(sun, sun.target);

// Ground and terrain. The ground's grid is a texture rather than lines: it is
// filtered into a plain tone far away, and no line ever crosses the camera.
const [gx0, gx1, gy0, gy1] = data.ground.extent;
function gridTexture(step) {
  const n = 512;
  const canvas = document.createElement("canvas");
  canvas.width = canvas.height = n;
  const g = canvas.getContext("2d");
  g.fillStyle = "#d9d9d6";
  g.fillRect(0, 0, n, n);
  const stroke = (color, width, at) => {
    g.strokeStyle = color;
    g.lineWidth = width;
    g.beginPath();
    for (const a of at) { g.moveTo(a, 0); g.lineTo(a, n); g.moveTo(0, a); g.lineTo(n, a); }
    g.stroke();
  };
  stroke("#b8b8b2", 3, [n / 4, n / 2, (3 * n) / 4]); // every step
  stroke("#98988f", 6, [0, n]); // every fourth step, half at each edge
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.anisotropy = renderer.capabilities.getMaxAnisotropy();
  const cell = 4 * step; // metres per texture tile
  texture.repeat.set((gx1 - gx0) / cell, (gy1 - gy0) / cell);
  texture.offset.set(gx0 / cell, gy0 / cell); // tile edges on multiples of the cell
  return texture;
}
const groundMaterial = new THREE.MeshStandardMaterial({ map: gridTexture(data.ground.grid), roughness: 1 });
const terrainMaterial = new THREE.MeshStandardMaterial({ color: 0xc2c2bc, roughness: 1 });
const ground = new THREE.Group();
const slope = data.ground.terrain.find((t) => t.kind === "slope");
{
  // Tilted about the origin, the plane's length along the slope covers 1/cos of it in x.
  const along = slope ? 1 / Math.cos(slope.angle) : 1;
  const plane = new THREE.Mesh(new THREE.PlaneGeometry((gx1 - gx0) * along, gy1 - gy0), groundMaterial);
  plane.position.set(((gx0 + gx1) / 2) * along, (gy0 + gy1) / 2, 0);
  plane.receiveShadow = true;
  ground.add(plane);
  if (slope) ground.rotation.y = -slope.angle;
}
scene.add(ground);
// A planar creature's terrain runs across the whole ground in y; drawn so, it would pass
// behind the side view's camera and fill the picture. Its blocks are a band around y = 0.
const band = data.planar ? 0.6 * data.size + Math.min(0.2, data.size) : Infinity; // a mite's camera is under a millimetre away
const [ty0, ty1] = [Math.max(gy0, -band), Math.min(gy1, band)];
for (const t of data.ground.terrain) {
  let box = null;
  if (t.kind === "step") box = [t.x, gx1, ty0, ty1, t.height];
  if (t.kind === "box") box = [t.x0, t.x1, Math.max(t.y0, ty0), Math.min(t.y1, ty1), t.height];
  if (!box) continue;
  const [x0, x1, y0, y1, h] = box;
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(x1 - x0, y1 - y0, h), terrainMaterial);
  mesh.position.set((x0 + x1) / 2, (y0 + y1) / 2, h / 2);
  mesh.receiveShadow = mesh.castShadow = true;
  const edges = new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry), new THREE.LineBasicMaterial({ color: 0x8c8c86 }));
  mesh.add(edges);
  scene.add(mesh);
}

// The paths the run followed: ribbons lying on the ground (pulled towards the camera in depth, so
// the ground never hides them; the creature does when it is in front).
const pathMaterial = new THREE.MeshBasicMaterial({ color: 0x1f6fd0, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2 });
const pathWidth = 0.04 * data.size;
// A run that changed to a controller following another path followed each over its own spans:
// at any time the path being followed is drawn as above, the others faded (where the creature
// came from and goes next stays in view, but one path is followed), with no lateral error.
const fadedPathMaterial = new THREE.MeshBasicMaterial({ color: 0x1f6fd0, side: THREE.DoubleSide, transparent: true, opacity: 0.25, depthWrite: false, polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2 });
const followedAt = (p, t) => !p.followed || p.followed.some(([a, b]) => t >= a - 1e-9 && t <= b + 1e-9);
const ribbons = [];
for (const p of data.paths || []) {
  const pts = f32(p.points);
  const n = pts.length / 3;
  if (n < 2) continue;
  const vertices = new Float32Array(6 * n);
  for (let i = 0; i < n; i++) {
    const a = Math.max(0, i - 1), b = Math.min(n - 1, i + 1);
    let tx = pts[3 * b] - pts[3 * a], ty = pts[3 * b + 1] - pts[3 * a + 1];
    const len = Math.hypot(tx, ty) || 1;
    tx /= len; ty /= len;
    for (const [k, side] of [[0, 1], [1, -1]]) {
      vertices[6 * i + 3 * k] = pts[3 * i] - side * ty * pathWidth / 2;
      vertices[6 * i + 3 * k + 1] = pts[3 * i + 1] + side * tx * pathWidth / 2;
      vertices[6 * i + 3 * k + 2] = pts[3 * i + 2] + Math.min(0.003, 0.01 * data.size); // just above the ground
    }
  }
  const indices = [];
  for (let i = 0; i + 1 < n; i++) indices.push(2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 1, 2 * i + 3, 2 * i + 2);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(vertices, 3));
  geometry.setIndex(indices);
  const ribbon = new THREE.Mesh(geometry, pathMaterial);
  ribbon.name = `path ${p.name}`;
  ribbon.renderOrder = 5;
  ribbon.frustumCulled = false;
  ribbon.userData.path = p;
  scene.add(ribbon);
  ribbons.push(ribbon);
}
// The lateral error: a segment on the ground from under the mass centre to the nearest path
// point, and its value in the panel.
const lateralTraces = (data.paths || []).filter((p) => p.nearest).map((p) => {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(6), 3));
  const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0x1f6fd0, depthTest: false }));
  line.renderOrder = 6;
  line.frustumCulled = false;
  scene.add(line);
  return { name: p.name, path: p, nearest: f32(p.nearest), lateral: f32(p.lateral), line };
});

// The creature.
const links = data.bodies.map((b) => {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(f32(b.mesh.positions), 3));
  geometry.setAttribute("normal", new THREE.BufferAttribute(f32(b.mesh.normals), 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(b.mesh.indices)), 1));
  const material = new THREE.MeshStandardMaterial({ color: b.color, roughness: 0.65, metalness: 0.0 });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = b.name;
  mesh.castShadow = mesh.receiveShadow = true;
  scene.add(mesh);
  return mesh;
});

// ------------------------------------------------------------------ overlays
const overlays = {
  state: { label: "state", on: data.overlays.includes("state") },
  speed: { label: "speed", on: data.overlays.includes("speed") },
  forces: { label: "forces", on: data.overlays.includes("forces") },
  footprints: { label: "footprints", on: data.overlays.includes("footprints") },
  com: { label: "COM trail", on: data.overlays.includes("com") },
};

// Force arrows: a shaft and a cone along +y (three's cylinder axis), turned
// to the force and scaled to its size; drawn over everything.
const arrowMaterial = new THREE.MeshBasicMaterial({ color: 0xd2401e, depthTest: false });
const shaftGeometry = new THREE.CylinderGeometry(1, 1, 1, 12).translate(0, 0.5, 0);
const headGeometry = new THREE.ConeGeometry(1, 1, 16).translate(0, 0.5, 0);
const arrows = [];
for (let c = 0; c < nContacts; c++) {
  const arrow = new THREE.Group();
  const shaft = new THREE.Mesh(shaftGeometry, arrowMaterial);
  const head = new THREE.Mesh(headGeometry, arrowMaterial);
  shaft.renderOrder = head.renderOrder = 20;
  arrow.add(shaft, head);
  arrow.visible = false;
  scene.add(arrow);
  arrows.push(arrow);
}
const yAxis = new THREE.Vector3(0, 1, 0);
function pointArrow(arrow, length) {
  const [shaft, head] = arrow.children;
  const headLength = Math.min(0.35 * length, 0.1 * data.size);
  const radius = Math.min(0.012 * data.size, 0.15 * headLength); // short arrows get thin
  shaft.scale.set(radius, length - headLength, radius);
  head.position.set(0, length - headLength, 0);
  head.scale.set(2.6 * radius, headLength, 2.6 * radius);
}
const arrowPerNewton = (0.6 * data.size) / data.weight; // the creature's weight is 0.6 sizes long

const footprintColors = [0x1f5fbf, 0x2a9d4b, 0xb8860b, 0x8e44ad, 0x16a085, 0xc0392b];
const footprintGeometry = new THREE.CircleGeometry(0.06 * data.size, 24);
const footprints = data.footprints.map(([t, c, x, y, z]) => {
  const mesh = new THREE.Mesh(footprintGeometry, new THREE.MeshBasicMaterial({ color: footprintColors[c % footprintColors.length], transparent: true, opacity: 0.75, depthWrite: false }));
  // on the ground where the foot stood (a touchdown point is a little in or above it), in its
  // plane, lifted off it along its normal
  const up = slope ? [-Math.sin(slope.angle), Math.cos(slope.angle)] : [0, 1];
  mesh.position.set(x + 0.002 * up[0], y, groundHeight(x, y) + 0.002 * up[1]);
  if (slope) mesh.rotation.y = -slope.angle;
  mesh.userData.t = t;
  scene.add(mesh);
  return mesh;
});

const trailGeometry = new THREE.BufferGeometry();
trailGeometry.setAttribute("position", new THREE.BufferAttribute(com, 3));
const trail = new THREE.Line(trailGeometry, new THREE.LineBasicMaterial({ color: 0xc0208a, depthTest: false }));
trail.renderOrder = 10;
trail.frustumCulled = false;
const comMarker = new THREE.Mesh(new THREE.SphereGeometry(0.03 * data.size, 16, 12), new THREE.MeshBasicMaterial({ color: 0xc0208a, depthTest: false }));
comMarker.renderOrder = 11;
scene.add(trail, comMarker);

// ------------------------------------------------------------------ camera
// The camera orbits a target that follows the mass centre horizontally, at
// a fixed height above the ground's plane (a slope's): hops and drops show as
// motion on the screen, and a climb stays in the picture. Where the creature would leave
// the default view at the top (a somersault's legs), the target rises smoothly by the
// run's `lift` (computed with the run, as the video's views use it: player/camera.py).
const lookHeight = data.lookHeight;
const defaults = data.planar
  ? { azimuth: -Math.PI / 2, elevation: 0.08, distance: data.distance }
  : { azimuth: -Math.PI / 3, elevation: 0.33, distance: data.distance };
const orbit = { ...defaults };
// the wheel zooms from 0.2 m to 100 m, or further for a creature that small or that large
const zoomRange = [Math.min(0.2, data.distance / 4), Math.max(100, 4 * data.distance)];
const target = new THREE.Vector3();

// The orbit's elevation is measured from the ground's plane: on a slope the orbit is tilted
// with it (as the video's camera), so the default view sees the slope as it sees level ground.
// Whatever the drag, the eye stays at least a tenth of the creature's size above that plane
// (a level orbit looked from under a steep slope, and a drag to -0.2 rad went under level
// ground): the elevation is raised to the least that keeps it there.
const tilt = slope ? slope.angle : 0;
function lowestElevation(distance, raised) {
  const above = (lookHeight + raised) * Math.cos(tilt); // the target's distance from the plane
  return Math.asin(Math.min(1, Math.max(-1, (0.1 * data.size - above) / distance)));
}
function placeCamera(raised) {
  const e = Math.max(orbit.elevation, lowestElevation(orbit.distance, raised));
  const c = Math.cos(e);
  const x = orbit.distance * c * Math.cos(orbit.azimuth), z = orbit.distance * Math.sin(e);
  camera.position.set(
    target.x + x * Math.cos(tilt) - z * Math.sin(tilt),
    target.y + orbit.distance * c * Math.sin(orbit.azimuth),
    target.z + x * Math.sin(tilt) + z * Math.cos(tilt),
  );
  camera.lookAt(target);
  sun.position.set(target.x + 4 * data.size, target.y - 3 * data.size, target.z + 8 * data.size);
  sun.target.position.copy(target);
}

let drag = null;
renderer.domElement.addEventListener("pointerdown", (e) => {
  drag = { x: e.clientX, y: e.clientY, azimuth: orbit.azimuth, elevation: orbit.elevation };
  renderer.domElement.setPointerCapture(e.pointerId);
});
renderer.domElement.addEventListener("pointermove", (e) => {
  if (!drag) return;
  orbit.azimuth = drag.azimuth - (e.clientX - drag.x) * 0.008;
  orbit.elevation = Math.min(1.5, Math.max(-0.2, drag.elevation + (e.clientY - drag.y) * 0.008));
  requestRender();
});
renderer.domElement.addEventListener("pointerup", () => { drag = null; });
renderer.domElement.addEventListener("wheel", (e) => {
  e.preventDefault();
  orbit.distance = Math.min(zoomRange[1], Math.max(zoomRange[0], orbit.distance * Math.exp(e.deltaY * 0.001)));
  requestRender();
}, { passive: false });
renderer.domElement.addEventListener("dblclick", () => { Object.assign(orbit, defaults); requestRender(); });

// ------------------------------------------------------------------ drawing a time
const qa = new THREE.Quaternion();
const qb = new THREE.Quaternion();
let time = 0;

function frameAt(t) {
  // Index of the last frame at or before t, and the fraction towards the next. A frame's
  // time is stored as a float32, so a time within a rounding of it counts as reaching it
  // (else the end of the run, or a time typed as 0.0833, reads the frame before's state).
  if (nFrames < 2) return [0, 0];
  const reached = (i) => times[i] <= t + 1e-6 * Math.max(Math.abs(t), 1e-9);
  if (reached(nFrames - 1)) return [nFrames - 1, 0];
  let lo = 0, hi = nFrames - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (reached(mid)) lo = mid; else hi = mid;
  }
  const a = Math.min(1, Math.max(0, (t - times[lo]) / (times[lo + 1] - times[lo])));
  return [lo, a];
}
const mix = (arr, i, j, a, k) => arr[i + k] + a * (arr[j + k] - arr[i + k]);

// Readouts in a unit their magnitudes read in: a 0.03 s run of a tiny hopper showed
// "0.00 / 0.03 s" and "speed: 0.00 m/s"; its times are in ms and its speeds in mm/s or um/s.
function unitFor(most, unit) {
  if (!(most > 0) || most >= 0.1) return { factor: 1, unit }; // 0, NaN, or large enough
  if (most >= 1e-3) return { factor: 1e3, unit: `m${unit}` };
  return { factor: 1e6, unit: `\u00b5${unit}` };
}
const timeUnit = unitFor(duration, "s");
let fastest = 0;
for (const v of [...speed, ...speedCommand]) if (Number.isFinite(v)) fastest = Math.max(fastest, Math.abs(v));
const speedUnit = unitFor(fastest, "m/s");
const inUnit = (x, u, digits) => `${fmt(x * u.factor, digits)} ${u.unit}`;

function fmt(x, digits = 2) {
  if (!Number.isFinite(x)) return "\u2013";
  const text = x.toFixed(digits);
  return Number(text) === 0 ? (0).toFixed(digits) : text; // no "-0.00"
}

function draw() {
  const [f, a] = frameAt(time);
  const g = Math.min(f + 1, nFrames - 1);
  for (let b = 0; b < nBodies; b++) {
    const i = (f * nBodies + b) * 7, j = (g * nBodies + b) * 7;
    links[b].position.set(mix(poses, i, j, a, 0), mix(poses, i, j, a, 1), mix(poses, i, j, a, 2));
    qa.set(poses[i + 3], poses[i + 4], poses[i + 5], poses[i + 6]);
    qb.set(poses[j + 3], poses[j + 4], poses[j + 5], poses[j + 6]);
    links[b].quaternion.slerpQuaternions(qa, qb, a);
  }
  const cx = mix(com, f * 3, g * 3, a, 0), cy = mix(com, f * 3, g * 3, a, 1), cz = mix(com, f * 3, g * 3, a, 2);
  const raised = mix(lift, f, g, a, 0);
  target.set(cx, data.planar ? 0 : cy, lookHeight + raised + slopeZ(cx));
  placeCamera(raised);

  for (let c = 0; c < nContacts; c++) {
    const i = (f * nContacts + c) * 3, j = (g * nContacts + c) * 3;
    const force = new THREE.Vector3(mix(forces, i, j, a, 0), mix(forces, i, j, a, 1), mix(forces, i, j, a, 2));
    const length = force.length() * arrowPerNewton;
    const arrow = arrows[c];
    arrow.visible = overlays.forces.on && length > 1e-3 * data.size;
    if (arrow.visible) {
      arrow.position.set(mix(contactPos, i, j, a, 0), mix(contactPos, i, j, a, 1), mix(contactPos, i, j, a, 2));
      arrow.quaternion.setFromUnitVectors(yAxis, force.normalize());
      pointArrow(arrow, length);
    }
  }
  for (const mesh of footprints) mesh.visible = overlays.footprints.on && mesh.userData.t <= time + 1e-9;
  for (const ribbon of ribbons) {
    ribbon.material = followedAt(ribbon.userData.path, time) ? pathMaterial : fadedPathMaterial;
  }
  for (const trace of lateralTraces) {
    trace.line.visible = followedAt(trace.path, time);
    const n = trace.nearest, at = trace.line.geometry.attributes.position;
    at.setXYZ(0, cx, cy, n[3 * f + 2] + 0.004);
    at.setXYZ(1, n[3 * f], n[3 * f + 1], n[3 * f + 2] + 0.004);
    at.needsUpdate = true;
  }
  trail.visible = comMarker.visible = overlays.com.on;
  trailGeometry.setDrawRange(0, f + 1);
  comMarker.position.set(cx, cy, cz);

  if (contextLost) draw2d(time, message.textContent);
  else renderer.render(scene, camera);
  api.renders += 1;
  updateHud(f);
}

// ------------------------------------------------------------------ HUD and controls
const hud = document.getElementById("hud");
const playButton = document.getElementById("play");
const scrub = document.getElementById("scrub");
const clock = document.getElementById("clock");
const rate = document.getElementById("rate");
const loop = document.getElementById("loop");
scrub.max = String(duration);

function escapeHtml(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
}

function updateHud(f) {
  const lines = [`<div class="title">${escapeHtml(data.creature)}</div>`];
  if (data.status !== "ok") lines.push(`<div class="bad">${escapeHtml(data.status)}: ${escapeHtml(data.message)}</div>`);
  lines.push(`<div>t = ${inUnit(time, timeUnit, 3)}</div>`);
  if (overlays.state.on) {
    const s = state[f];
    const name = s >= 0 && s < data.stateNames.length ? escapeHtml(data.stateNames[s]) : '<span class="dim">no controller</span>';
    lines.push(`<div>state: <b id="state-name">${name}</b></div>`);
  }
  if (overlays.speed.on) {
    const command = Number.isFinite(speedCommand[f]) ? inUnit(speedCommand[f], speedUnit, 2) : '<span class="dim">none</span>';
    lines.push(`<div>speed: ${inUnit(speed[f], speedUnit, 2)} &middot; command: ${command}</div>`);
  }
  for (const trace of lateralTraces) {
    const name = `path ${escapeHtml(trace.name)}`;
    if (followedAt(trace.path, time)) lines.push(`<div>${name}: lateral error <span class="lateral">${fmt(trace.lateral[f])}</span> m</div>`);
    else {
      const when = trace.path.followed.map(([a, b]) => `${fmt(a)} to ${fmt(b)} s`).join(", ");
      lines.push(`<div class="dim">${name}: not followed now (${when})</div>`);
    }
  }
  hud.innerHTML = lines.join("");
  clock.textContent = `${fmt(time * timeUnit.factor, 2)} / ${inUnit(duration, timeUnit, 2)}`;
  scrub.value = String(time);
  playButton.innerHTML = playing ? "&#10074;&#10074;" : "&#9654;";
}

const overlayBox = document.getElementById("overlays");
for (const [key, o] of Object.entries(overlays)) {
  const label = document.createElement("label");
  const box = document.createElement("input");
  box.type = "checkbox";
  box.id = `overlay-${key}`;
  box.checked = o.on;
  box.addEventListener("change", () => { o.on = box.checked; requestRender(); });
  label.append(box, ` ${o.label}`);
  overlayBox.append(label);
}

let playing = false;
let last = null;
function setPlaying(on) {
  playing = on && duration > 0;
  if (playing && time >= duration) time = 0;
  last = null;
  requestRender();
}
playButton.addEventListener("click", () => setPlaying(!playing));
scrub.addEventListener("input", () => { playing = false; time = Number(scrub.value); requestRender(); });
window.addEventListener("keydown", (e) => {
  if (e.target instanceof HTMLSelectElement) return;
  if (e.code === "Space") { e.preventDefault(); setPlaying(!playing); }
  const step = nFrames > 1 ? duration / (nFrames - 1) : 0;
  if (e.code === "ArrowRight") { playing = false; time = Math.min(duration, time + step); requestRender(); }
  if (e.code === "ArrowLeft") { playing = false; time = Math.max(0, time - step); requestRender(); }
});

let pending = false;
function requestRender() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(tick);
}
function tick(now) {
  pending = false;
  if (playing) {
    if (last !== null) time += ((now - last) / 1000) * Number(rate.value);
    last = now;
    if (time >= duration) {
      if (loop.checked) time %= duration || 1;
      else { time = duration; playing = false; }
    }
  }
  draw();
  if (playing) requestRender();
}

// Setting a canvas's size clears it, even to the size it has: resize only on a real change,
// and draw again at once (not at the next animation frame), so that no picture (a headless
// screenshot among them) is ever taken of a cleared canvas.
let drawnSize = "";
function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  if (`${w}x${h}` === drawnSize) return;
  drawnSize = `${w}x${h}`;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
  draw();
}
new ResizeObserver(() => resize()).observe(view); // the window, or the control bar wrapping

// ------------------------------------------------------------------ scripting interface (tests, consoles)
const api = {
  ready: false,
  renders: 0,
  duration,
  frames: nFrames,
  threeVersion: THREE.REVISION,
  setTime(t) { playing = false; time = Math.min(duration, Math.max(0, t)); draw(); },
  getTime: () => time,
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  isPlaying: () => playing,
  setRate(r) { rate.value = String(r); },
  setOverlay(name, on) { api.setOverlays({ [name]: on }); },
  setOverlays(settings) {
    for (const [name, on] of Object.entries(settings)) {
      overlays[name].on = on;
      document.getElementById(`overlay-${name}`).checked = on;
    }
    draw();
  },
  // Where a world point is drawn, in CSS pixels of the page.
  project(x, y, z) {
    const p = new THREE.Vector3(x, y, z).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
  },
  bodyPosition: (i) => links[i].position.toArray(),
  // A point given in body i's frame, in world coordinates.
  bodyPoint: (i, p) => new THREE.Vector3(...p).applyMatrix4(links[i].matrixWorld).toArray(),
  setView(v) { Object.assign(orbit, v); draw(); },
  scene, // for poking at from a browser console
  redraw: () => draw(),
  getView: () => ({ ...orbit }),
  cameraPosition: () => camera.position.toArray(),
  cameraTarget: () => target.toArray(),
  // Each path's name and whether it is drawn as followed (not faded) at the current time.
  pathsShown: () => ribbons.map((r) => [r.userData.path.name, r.material === pathMaterial]),
  isFlat: () => flat.on,
  // For tests: lose the WebGL context (and get it back) as a failing GPU would.
  loseContext() { api.lost = renderer.getContext().getExtension("WEBGL_lose_context"); api.lost.loseContext(); },
  restoreContext() { api.lost.restoreContext(); },
};
window.legdsl = api;
resize();
draw();
api.ready = true;
