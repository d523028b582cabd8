// Colony's live viewer: draws a served run with three.js (Debian's
// libjs-three, r111) and steers it. The protocol is in docs/viewer.md: a
// JSON scene once, binary frames of poses and LED colours, JSON commands.
//
// Robots are drawn with one InstancedMesh per part per robot type, so 10,000
// robots cost a few draw calls. Every part is modelled in "robot units"
// (x and y in radii, z in heights, origin at the centre of the base, +x the
// heading); one matrix per robot (pose, then scale by its size) places all
// its parts. Per-robot colours (body, LEDs) are an instanced "color"
// attribute read through vertexColors.
import * as THREE from '/three/build/three.module.js';
import { OrbitControls } from '/three/examples/jsm/controls/OrbitControls.js';
import { CSS2DRenderer, CSS2DObject } from '/three/examples/jsm/renderers/CSS2DRenderer.js';

const FRAME_MAGIC = 0x31464C43;  // "CLF1"
const DRAWING_MAGIC = 0x31444C43;  // "CLD1": what the loop functions drew follows the records
const HEADER_BYTES = 16, RECORD_BYTES = 20;
// Robot ids are written over every robot up to this many robots; above it,
// over the selected one only (10,000 labels would cost more than the scene).
const MAX_ID_LABELS = 300;
// Positions a trail keeps (one per frame received).
const TRAIL_LENGTH = 60;

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(0x20242a);
view.appendChild(renderer.domElement);
// Text (robot ids, loop functions' text) as HTML labels over the canvas.
const labels = new CSS2DRenderer();
labels.setSize(window.innerWidth, window.innerHeight);
labels.domElement.style.position = 'absolute';
labels.domElement.style.top = '0';
labels.domElement.style.pointerEvents = 'none';
labels.domElement.style.zIndex = '0';  // its labels' own z-indexes stay under the panels
view.appendChild(labels.domElement);

const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, 0.01, 1000);
camera.up.set(0, 0, 1);  // the simulation's z is up
const controls = new OrbitControls(camera, renderer.domElement);
controls.screenSpacePanning = true;
controls.addEventListener('change', () => { needsRender = true; });

const world = new THREE.Scene();
world.add(new THREE.HemisphereLight(0xffffff, 0x555555, 0.75));
const sun = new THREE.DirectionalLight(0xffffff, 0.55);
sun.position.set(-0.35, -0.5, 1);
world.add(sun);

let scene = null;        // the scene description (JSON)
let arena = null;        // THREE.Group: floor, grid, fixed objects
let groups = [];         // per robot type: { parts, members, ... }
let movers = [];         // per mover: { desc, group, index, scale, pose, led }
let tick = 0, playing = false, done = false, speed = 1, moved = false;
let selected = -1;
let needsRender = true;
let socket = null;

const highlight = new THREE.Mesh(new THREE.RingBufferGeometry(1.25, 1.45, 32),
                                 new THREE.MeshBasicMaterial({ color: 0xffdd00, side: THREE.DoubleSide }));
highlight.visible = false;
world.add(highlight);

// Overlays, switched on the page (or with ?overlays=ids,trails,rays,links,fov
// in the address): robot ids, trails, the selected robot's proximity rays,
// range-and-bearing links and cameras' fields of view. Drawn from what the page already has (frames,
// the selected robot's inspection), so they cost the simulator nothing.
const overlays = { ids: false, trails: false, rays: false, allrays: false, links: false, fov: false };
for (const name of (new URLSearchParams(location.search).get('overlays') || '').split(',')) {
  if (name in overlays) overlays[name] = true;
}
const overlayGroup = new THREE.Group();  // rebuilt when a frame or an inspection arrives
world.add(overlayGroup);
const drawnGroup = new THREE.Group();  // what the loop functions drew, from the last frame
world.add(drawnGroup);
let trails = [];  // per mover: a Float32Array ring of x, y, z and how many it holds
let trailHead = 0, trailCount = 0;
let drawnCount = { points: 0, lines: 0, circles: 0, texts: 0 };
let overlayLines = 0;  // segments the overlays hold (trails, rays, links)

// --- Parts of robots, in robot units -------------------------------------

// An upright cylinder from z0 to z1 (robot units) of radius r, centred at (x, y).
function cylinder(r, z0, z1, x = 0, y = 0, segments = 24) {
  const g = new THREE.CylinderBufferGeometry(r, r, z1 - z0, segments);
  g.rotateX(Math.PI / 2);
  g.translate(x, y, (z0 + z1) / 2);
  return g;
}
// A box of size (sx, sy, sz) whose base is centred at (x, y, z0).
function box(sx, sy, sz, x = 0, y = 0, z0 = 0) {
  const g = new THREE.BoxBufferGeometry(sx, sy, sz);
  g.translate(x, y, z0 + sz / 2);
  return g;
}
function torus(radius, tube, z) {
  const g = new THREE.TorusBufferGeometry(radius, tube, 6, 40);
  g.translate(0, 0, z);
  return g;
}

// colour: 'body' (the entity's colour), 'led' (from the frames) or a fixed RGB hex.
// glow: drawn unlit (LEDs).
function partsOf(desc) {
  const dark = 0x2a2a30, plate = 0xaaaaaa, metal = 0x9696a0;
  switch (desc.type) {
    case 'marxbot':  // treels and body, LED ring, top plate, the camera housing at the front
      return [
        { geometry: cylinder(1, 0, 0.62), color: 'body' },
        { geometry: cylinder(0.82, 0.62, 0.82), color: 'body' },
        { geometry: cylinder(0.9, 0.82, 0.92), color: 'led', glow: true },
        { geometry: cylinder(0.7, 0.92, 1.0), color: plate },
        { geometry: box(0.45, 0.35, 0.08, 0.5, 0, 1.0), color: dark },
      ];
    case 'handbot':  // hull, LED ring, launcher on top, head and arms reaching forward
      return [
        { geometry: cylinder(1, 0, 0.38), color: 'body' },
        { geometry: cylinder(0.9, 0.38, 0.46), color: 'led', glow: true },
        { geometry: cylinder(1, 0.46, 0.76), color: 'body' },
        { geometry: cylinder(0.24, 0.76, 1.0, 0, 0, 8), color: dark },
        { geometry: box(0.45, 0.7, 0.12, 0.75, 0, 0.6), color: metal },
        { geometry: box(0.9, 0.12, 0.08, 1.3, 0.45, 0.62), color: metal },
        { geometry: box(0.9, 0.12, 0.08, 1.3, -0.45, 0.62), color: metal },
      ];
    case 'eyebot': {  // legs, body, RGB LED collar, rotors on the diagonals, protective ring
      const parts = [
        { geometry: cylinder(0.28, 0.33, 0.8), color: 'body' },
        { geometry: cylinder(0.2, 0.8, 1.0), color: metal },
        { geometry: cylinder(0.22, 0.28, 0.33), color: 'led', glow: true },
        { geometry: torus(0.97, 0.03, 0.67), color: metal },
        { geometry: box(0.16, 0.16, 0.04, 0.2, 0, 1.0), color: dark },
      ];
      for (let k = 0; k < 4; ++k) {
        const a = Math.PI / 4 + k * Math.PI / 2, c = Math.cos(a) * 0.6, s = Math.sin(a) * 0.6;
        parts.push({ geometry: cylinder(0.38, 0.68, 0.71, c, s, 16), color: 0x6e6e73 });
        parts.push({ geometry: box(0.05, 0.05, 0.6, c * 0.6, s * 0.6, 0), color: dark });
      }
      return parts;
    }
    default: {
      const shape = desc.shape === 'box' ? box(2, 2, 1) : cylinder(1, 0, 1);
      if (!desc.robot) return [{ geometry: shape, color: 'led' }];  // its colour, from the frames
      // Another robot type: its shape, an LED disc on top and a heading mark.
      return [
        { geometry: shape, color: 'body' },
        { geometry: cylinder(0.6, 1.0, 1.04), color: 'led', glow: true },
        { geometry: box(0.5, 0.3, 0.06, 0.55, 0, 1.0), color: dark },
      ];
    }
  }
}

// One InstancedMesh per part for the `members` (mover indices) of one group.
function buildGroup(key, members) {
  const desc = movers[members[0]].desc;
  const n = members.length;
  const parts = partsOf(desc).map((spec) => {
    const geometry = spec.geometry;
    let material;
    if (typeof spec.color === 'number') {
      material = new THREE.MeshLambertMaterial({ color: spec.color });
    } else {
      const colors = new THREE.InstancedBufferAttribute(new Float32Array(n * 3), 3);
      if (spec.color === 'body') {
        members.forEach((m, i) => {
          const c = movers[m].desc.color;
          colors.setXYZ(i, c[0] / 255, c[1] / 255, c[2] / 255);
        });
      }
      geometry.setAttribute('color', colors);
      const options = { vertexColors: THREE.VertexColors };
      material = spec.glow ? new THREE.MeshBasicMaterial(options) : new THREE.MeshLambertMaterial(options);
    }
    const mesh = new THREE.InstancedMesh(geometry, material, n);
    mesh.frustumCulled = false;  // its bounds are the unit robot's, not the swarm's
    world.add(mesh);
    return { mesh, led: spec.color === 'led' ? geometry.getAttribute('color') : null };
  });
  members.forEach((m, i) => { movers[m].group = groups.length; movers[m].index = i; });
  groups.push({ key, parts, members });
}

// --- Scene ----------------------------------------------------------------

function clearScene() {
  if (arena) world.remove(arena);
  for (const g of groups) {
    for (const p of g.parts) {
      world.remove(p.mesh);
      p.mesh.geometry.dispose();
      p.mesh.material.dispose();
    }
  }
  groups = [];
  movers = [];
}

function color3(rgb) { return new THREE.Color(rgb[0] / 255, rgb[1] / 255, rgb[2] / 255); }

function buildArena(desc) {
  const group = new THREE.Group();
  const [x0, y0, z0] = desc.arena.min, [x1, y1] = desc.arena.max;
  const floor = new THREE.Mesh(new THREE.PlaneBufferGeometry(x1 - x0, y1 - y0),
                               new THREE.MeshLambertMaterial({ color: color3(desc.floor.color) }));
  floor.position.set((x0 + x1) / 2, (y0 + y1) / 2, z0);
  group.add(floor);
  // Grid lines: 1 m apart, 10 times farther until at most 100 cross a side.
  let spacing = 1;
  while (Math.max(x1 - x0, y1 - y0) / spacing > 100) spacing *= 10;
  const points = [];
  for (let x = Math.ceil(x0 / spacing) * spacing; x <= x1; x += spacing) points.push(x, y0, z0 + 0.001, x, y1, z0 + 0.001);
  for (let y = Math.ceil(y0 / spacing) * spacing; y <= y1; y += spacing) points.push(x0, y, z0 + 0.001, x1, y, z0 + 0.001);
  const grid = new THREE.BufferGeometry();
  grid.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  group.add(new THREE.LineSegments(grid, new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.15 })));
  for (const d of desc.floor.ditches) {
    const pit = new THREE.Mesh(new THREE.PlaneBufferGeometry(d.max[0] - d.min[0], d.max[1] - d.min[1]),
                               new THREE.MeshBasicMaterial({ color: 0x111111 }));
    pit.position.set((d.min[0] + d.max[0]) / 2, (d.min[1] + d.max[1]) / 2, z0 + 0.002);
    group.add(pit);
  }
  for (const o of desc.objects) {
    const holder = new THREE.Group();
    holder.position.set(...o.position);
    const [w, qx, qy, qz] = o.orientation;
    holder.quaternion.set(qx, qy, qz, w);
    let mesh = null;
    if (o.light) {
      mesh = new THREE.Mesh(new THREE.SphereBufferGeometry(0.03, 12, 8), new THREE.MeshBasicMaterial({ color: color3(o.color) }));
    } else if (o.shape === 'box') {
      mesh = new THREE.Mesh(box(o.size[0], o.size[1], o.size[2]), new THREE.MeshLambertMaterial({ color: color3(o.color) }));
    } else if (o.shape === 'cylinder') {
      mesh = new THREE.Mesh(cylinder(o.radius, 0, o.size[2], 0, 0, 32), new THREE.MeshLambertMaterial({ color: color3(o.color) }));
    }
    if (!mesh) continue;
    mesh.userData.id = o.id;
    holder.add(mesh);
    group.add(holder);
  }
  return group;
}

function buildScene(desc) {
  clearScene();
  scene = desc;
  arena = buildArena(desc);
  world.add(arena);
  movers = desc.movers.map((d) => ({
    desc: d,
    group: -1,
    index: -1,
    // Robot units to metres: radii across, height up.
    scale: d.shape === 'box' ? [d.size[0] / 2, d.size[1] / 2, d.size[2]] : [d.radius, d.radius, d.size[2]],
    pose: [0, 0, 0, 0],
    led: [0, 0, 0],
  }));
  const byType = new Map();
  movers.forEach((m, i) => {
    const key = (m.desc.robot ? 'robot:' : 'object:') + m.desc.type + ':' + m.desc.shape;
    if (!byType.has(key)) byType.set(key, []);
    byType.get(key).push(i);
  });
  for (const [key, members] of byType) buildGroup(key, members);
  if (selected >= movers.length) selected = -1;
  // ?select=ID in the page's address selects that robot once (for links and tests).
  const wanted = new URLSearchParams(location.search).get('select');
  if (wanted && !selectedFromAddress) {
    selectedFromAddress = true;
    selected = movers.findIndex((m) => m.desc.id === wanted);
    askInspect();
  }
  const first = !camera.userData.placed;
  if (first) perspectiveView();
  needsRender = true;
}

// --- Frames ---------------------------------------------------------------

const matrix = new THREE.Matrix4(), position = new THREE.Vector3(), turn = new THREE.Quaternion();
const scaleVec = new THREE.Vector3(), zAxis = new THREE.Vector3(0, 0, 1);

function applyFrame(buffer) {
  const data = new DataView(buffer);
  if (buffer.byteLength < HEADER_BYTES || data.getUint32(0, true) !== FRAME_MAGIC) {
    return showMessage('a frame that is not one (bad magic) was ignored');
  }
  const count = data.getUint32(4, true);
  if (!scene || count !== movers.length || buffer.byteLength < HEADER_BYTES + RECORD_BYTES * count) {
    return showMessage(`a frame of ${count} movers does not match the scene's ${movers.length}; ignored`);
  }
  tick = Number(data.getBigUint64(8, true));
  for (let i = 0; i < count; ++i) {
    const o = HEADER_BYTES + RECORD_BYTES * i;
    const m = movers[i];
    const x = data.getFloat32(o, true), y = data.getFloat32(o + 4, true);
    const z = data.getFloat32(o + 8, true), yaw = data.getFloat32(o + 12, true);
    m.pose[0] = x; m.pose[1] = y; m.pose[2] = z; m.pose[3] = yaw;
    m.led[0] = data.getUint8(o + 16); m.led[1] = data.getUint8(o + 17); m.led[2] = data.getUint8(o + 18);
    position.set(x, y, z);
    turn.setFromAxisAngle(zAxis, yaw);
    scaleVec.set(m.scale[0], m.scale[1], m.scale[2]);
    matrix.compose(position, turn, scaleVec);
    for (const part of groups[m.group].parts) {
      matrix.toArray(part.mesh.instanceMatrix.array, m.index * 16);
      if (part.led) part.led.setXYZ(m.index, m.led[0] / 255, m.led[1] / 255, m.led[2] / 255);
    }
  }
  for (const g of groups) {
    for (const part of g.parts) {
      part.mesh.instanceMatrix.needsUpdate = true;
      if (part.led) part.led.needsUpdate = true;
    }
  }
  recordTrails();
  applyDrawing(data, HEADER_BYTES + RECORD_BYTES * count);
  rebuildOverlays();
  needsRender = true;
  framesApplied = true;
}
let framesApplied = false;

// --- What the loop functions drew ----------------------------------------

function disposeGroup(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    if (child.geometry) child.geometry.dispose();
    if (child.material) child.material.dispose();
  }
}
function rgbOf(data, at) {
  return new THREE.Color(data.getUint8(at) / 255, data.getUint8(at + 1) / 255, data.getUint8(at + 2) / 255);
}
function textLabel(text, rgb, className) {
  const div = document.createElement('div');
  div.className = className;
  div.textContent = text;
  div.style.color = `rgb(${rgb.r * 255}, ${rgb.g * 255}, ${rgb.b * 255})`;
  return new CSS2DObject(div);
}
function xyzAt(data, at) {
  return [data.getFloat32(at, true), data.getFloat32(at + 4, true), data.getFloat32(at + 8, true)];
}

// The drawing section (docs/viewer.md): points, polylines, circles in the
// horizontal plane, text; none when the frame ends after its records.
function applyDrawing(data, at) {
  disposeGroup(drawnGroup);
  drawnCount = { points: 0, lines: 0, circles: 0, texts: 0 };
  if (data.byteLength <= at) return;
  if (data.byteLength < at + 20 || data.getUint32(at, true) !== DRAWING_MAGIC) {
    return showMessage('a frame with a bad drawing section: its shapes are not shown');
  }
  const [points, lines, circles, texts] = [4, 8, 12, 16].map((k) => data.getUint32(at + k, true));
  at += 20;
  const segments = [], segmentColors = [];
  const addSegment = (a, b, c) => { segments.push(...a, ...b); segmentColors.push(c.r, c.g, c.b, c.r, c.g, c.b); };
  try {
    for (let k = 0; k < points; ++k, at += 20) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(xyzAt(data, at), 3));
      const m = new THREE.PointsMaterial({ color: rgbOf(data, at + 16), size: data.getFloat32(at + 12, true),
                                           sizeAttenuation: false, depthTest: false });
      drawnGroup.add(new THREE.Points(g, m));
    }
    for (let k = 0; k < lines; ++k) {
      const n = data.getUint32(at, true), c = rgbOf(data, at + 4), closed = data.getUint8(at + 8) !== 0;
      at += 9;
      const ps = [];
      for (let j = 0; j < n; ++j, at += 12) ps.push(xyzAt(data, at));
      for (let j = 1; j < n; ++j) addSegment(ps[j - 1], ps[j], c);
      if (closed && n > 2) addSegment(ps[n - 1], ps[0], c);
    }
    for (let k = 0; k < circles; ++k, at += 21) {
      const [x, y, z] = xyzAt(data, at), r = data.getFloat32(at + 12, true);
      const c = rgbOf(data, at + 16), alpha = data.getUint8(at + 19) / 255, filled = data.getUint8(at + 20) !== 0;
      if (filled) {
        const disc = new THREE.Mesh(new THREE.CircleBufferGeometry(r, 64),
                                    new THREE.MeshBasicMaterial({ color: c, transparent: alpha < 1, opacity: alpha,
                                                                  side: THREE.DoubleSide, depthWrite: false }));
        disc.position.set(x, y, z + 0.001);
        drawnGroup.add(disc);
      } else {
        for (let j = 0; j < 64; ++j) {
          const a0 = j / 64 * 2 * Math.PI, a1 = (j + 1) / 64 * 2 * Math.PI;
          addSegment([x + r * Math.cos(a0), y + r * Math.sin(a0), z + 0.001],
                     [x + r * Math.cos(a1), y + r * Math.sin(a1), z + 0.001], c);
        }
      }
    }
    for (let k = 0; k < texts; ++k) {
      const p = xyzAt(data, at), c = rgbOf(data, at + 12), n = data.getUint16(at + 16, true);
      const text = new TextDecoder().decode(new Uint8Array(data.buffer, data.byteOffset + at + 18, n));
      at += 18 + n;
      const label = textLabel(text, c, 'drawn-text');
      label.position.set(...p);
      drawnGroup.add(label);
    }
  } catch (e) {
    disposeGroup(drawnGroup);
    return showMessage('a frame with a drawing section cut short: its shapes are not shown');
  }
  if (segments.length) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(segments, 3));
    g.setAttribute('color', new THREE.Float32BufferAttribute(segmentColors, 3));
    drawnGroup.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })));
  }
  drawnCount = { points, lines, circles, texts };
}

// --- Overlays -------------------------------------------------------------

// Each mover's last TRAIL_LENGTH positions, from the frames (only while trails are on).
function recordTrails() {
  if (!overlays.trails) { trails = []; trailCount = 0; return; }
  if (trails.length !== movers.length) {
    trails = movers.map(() => new Float32Array(3 * TRAIL_LENGTH));
    trailHead = 0; trailCount = 0;
  }
  movers.forEach((m, i) => { trails[i].set([m.pose[0], m.pose[1], m.pose[2] + 0.002], 3 * trailHead); });
  trailHead = (trailHead + 1) % TRAIL_LENGTH;
  trailCount = Math.min(trailCount + 1, TRAIL_LENGTH);
}

function rebuildOverlays() {
  disposeGroup(overlayGroup);
  const lines = [], colors = [];
  const add = (a, b, c) => { lines.push(...a, ...b); colors.push(...c, ...c); };
  if (overlays.trails && trailCount > 1) {
    for (const ring of trails) {
      for (let k = 1; k < trailCount; ++k) {
        const i0 = (trailHead - trailCount + k - 1 + TRAIL_LENGTH) % TRAIL_LENGTH, i1 = (i0 + 1) % TRAIL_LENGTH;
        const fade = 0.25 + 0.75 * k / trailCount;
        add(ring.subarray(3 * i0, 3 * i0 + 3), ring.subarray(3 * i1, 3 * i1 + 3), [0.12 * fade, 0.43 * fade, 0.9 * fade]);
      }
    }
  }
  const info = selected >= 0 && inspected && inspected.id === movers[selected].desc.id ? inspected : null;
  if (info && info.sensors) {
    const [x, y, z, yaw] = movers[selected].pose;
    for (const d of info.sensors) {
      if (overlays.rays && !overlays.allrays && d.kind === 'proximity' && d.rays) {
        for (const r of d.rays) add([r[0], r[1], r[2]], [r[3], r[4], r[2]], r[5] ? [1, 0.16, 0.63] : [0.16, 0.78, 0.94]);
      }
      if (overlays.fov && d.fov) {
        for (const s of d.fov) add([s[0], s[1], s[2]], [s[3], s[4], s[5]], [1, 0.82, 0.16]);
      }
      if (overlays.links && d.kind === 'range_and_bearing') {
        for (const p of d.packets) {
          const a = yaw + p.bearing, flat = p.range * Math.cos(p.elevation || 0);
          add([x, y, z + 0.1], [x + flat * Math.cos(a), y + flat * Math.sin(a), z + 0.1 + p.range * Math.sin(p.elevation || 0)], [1, 0.8, 0.1]);
        }
      }
    }
  }
  if (overlays.allrays && allRays) {
    for (const rays of Object.values(allRays.robots)) {
      for (const r of rays) add([r[0], r[1], r[2]], [r[3], r[4], r[2]], r[5] ? [1, 0.16, 0.63] : [0.16, 0.78, 0.94]);
    }
  }
  if (lines.length) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(lines, 3));
    g.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
    overlayGroup.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })));
  }
  if (overlays.ids) {
    const shown = movers.length <= MAX_ID_LABELS ? movers.map((m, i) => i) : selected >= 0 ? [selected] : [];
    for (const i of shown) {
      const m = movers[i];
      if (!m.desc.robot) continue;
      const label = textLabel(m.desc.id, new THREE.Color(1, 1, 1), 'robot-id');
      label.position.set(m.pose[0], m.pose[1], m.pose[2] + m.scale[2] + 0.02);
      overlayGroup.add(label);
    }
  }
  document.body.dataset.overlays = Object.keys(overlays).filter((k) => overlays[k]).join(',');
  overlayLines = lines.length / 6;
  needsRender = true;
}


// --- Views and picking ----------------------------------------------------

function arenaCentreAndSpan() {
  const [x0, y0, z0] = scene.arena.min, [x1, y1] = scene.arena.max;
  return { c: new THREE.Vector3((x0 + x1) / 2, (y0 + y1) / 2, z0), span: Math.max(x1 - x0, y1 - y0) };
}
function placeCamera(offset) {
  if (!scene) return;
  const { c, span } = arenaCentreAndSpan();
  camera.near = span / 2000;
  camera.far = span * 50;
  camera.updateProjectionMatrix();
  controls.target.copy(c);
  camera.position.copy(c).addScaledVector(offset, span);
  camera.userData.placed = true;
  controls.update();
  needsRender = true;
}
function perspectiveView() { placeCamera(new THREE.Vector3(0, -0.95, 0.8)); }
// Straight down, north up (a hair off vertical: the orbit controls' pole).
function topView() { placeCamera(new THREE.Vector3(0, -1e-4, 1.25)); }

// The mover drawn nearest to the pointer, within a few pixels of its body.
function pick(clientX, clientY) {
  const rect = renderer.domElement.getBoundingClientRect();
  const p = new THREE.Vector3();
  let best = -1, bestDistance = Infinity;
  movers.forEach((m, i) => {
    p.set(m.pose[0], m.pose[1], m.pose[2] + m.scale[2] / 2).project(camera);
    if (p.z > 1) return;  // behind the camera
    const sx = (p.x + 1) / 2 * rect.width + rect.left, sy = (1 - p.y) / 2 * rect.height + rect.top;
    const d = Math.hypot(sx - clientX, sy - clientY);
    if (d < bestDistance) { bestDistance = d; best = i; }
  });
  if (best < 0) return -1;
  // Its radius on screen, at least 12 pixels.
  const m = movers[best];
  const dist = camera.position.distanceTo(new THREE.Vector3(m.pose[0], m.pose[1], m.pose[2]));
  const pixels = m.scale[0] / (dist * Math.tan(camera.fov * Math.PI / 360)) * rect.height / 2;
  return bestDistance <= Math.max(12, 1.5 * pixels) ? best : -1;
}

// The last inspection reply (sensors, actuators, controller values) of the
// selected robot, and when the next may be asked for.
let inspected = null, inspectAsked = 0, inspectTick = -1, selectedFromAddress = false;

function askInspect() {
  if (selected < 0) return;
  inspectAsked = performance.now();
  inspectTick = tick;
  send({ cmd: 'inspect', id: movers[selected].desc.id });
}
// While a robot is selected, its readings follow the run: asked again when
// the tick changed, at most 3 times a second.
function refreshInspect() {
  if (selected >= 0 && tick !== inspectTick && performance.now() - inspectAsked > 330) askInspect();
  refreshAllRays();
}

// Every robot's proximity rays (the "all rays" overlay, up to 300 robots):
// asked for as the inspection is, when the tick changed, at most 3 times a second.
let allRays = null, allRaysAsked = 0, allRaysTick = -1;
function refreshAllRays() {
  if (!overlays.allrays || tick === allRaysTick || performance.now() - allRaysAsked < 330) return;
  if (movers.filter((m) => m.desc.robot).length > 300) return;
  allRaysAsked = performance.now();
  allRaysTick = tick;
  send({ cmd: 'rays' });
}

function fixed(v, digits = 3) {
  return typeof v === 'number' && !Number.isInteger(v) ? v.toFixed(digits) : String(v);
}
function tuple(x) { return Array.isArray(x) ? `(${x.map((y) => fixed(y, 2)).join(', ')})` : fixed(x); }

// One device's lines: a ring's values 8 to a line, other fields one a line.
function deviceLines(d) {
  const name = d.kind && d.kind !== d.label ? `${d.label} (${d.kind})` : d.label;
  if (d.shown === false) return [`${name}: not shown`];
  if (d.values) {
    const lines = [`${name}: ${d.values.length} readings`];
    for (let i = 0; i < d.values.length; i += 8) {
      lines.push('  ' + d.values.slice(i, i + 8).map((v) => v.toFixed(2)).join(' '));
    }
    return lines;
  }
  const lines = [name + ':'];
  for (const [k, v] of Object.entries(d)) {
    if (k === 'label' || k === 'kind') continue;
    let text;
    if (Array.isArray(v)) {
      const shown = v.map(tuple);
      if (shown.length > 1 && shown.every((t) => t === shown[0])) text = `${shown.length} x ${shown[0]}`;
      else text = shown.length > 12 ? `${shown.length} items` : shown.join(' ');
    } else text = fixed(v);
    lines.push(`  ${k} ${text}`);
  }
  return lines;
}

function showInspect() {
  const panel = document.getElementById('inspect');
  if (selected < 0) { panel.hidden = true; highlight.visible = false; return; }
  const m = movers[selected];
  const [x, y, z, yaw] = m.pose;
  panel.hidden = false;
  const lines = [
    `${m.desc.id}  (${m.desc.type}${m.desc.robot ? '' : ', object'})`,
    `x   ${x.toFixed(3)} m`, `y   ${y.toFixed(3)} m`, `z   ${z.toFixed(3)} m`,
    `yaw ${(yaw * 180 / Math.PI).toFixed(1)} deg`, `LED ${m.led.join(', ')}`, `tick ${tick}`];
  const info = inspected && inspected.id === m.desc.id ? inspected : null;
  if (info && info.controller) {
    lines.push('', `controller ${info.controller}  (read at tick ${info.tick})`, '', 'sensors');
    for (const d of info.sensors) lines.push(...deviceLines(d).map((l) => '  ' + l));
    lines.push('actuators');
    for (const d of info.actuators) lines.push(...deviceLines(d).map((l) => '  ' + l));
    const values = Object.entries(info.values);
    if (values.length) {
      lines.push('values');
      for (const [k, v] of values) lines.push(`  ${k} ${fixed(v)}`);
    }
    if (info.log && info.log.length) {
      lines.push('log (last lines)');
      for (const l of info.log) lines.push('  ' + l);
    }
  }
  if (!playing && !done) lines.push('', 'shift + drag: move it');
  panel.textContent = lines.join('\n');
  highlight.visible = true;
  const at = dragging >= 0 && dragTo ? dragTo : [x, y];
  highlight.position.set(at[0], at[1], z + 0.002);
  highlight.scale.set(m.scale[0], m.scale[1], 1);
  document.body.dataset.inspected = info ? info.id : '';
}

// --- Messages and controls ------------------------------------------------

let messageTimer = null;
function showMessage(text) {
  const box = document.getElementById('message');
  box.textContent = text;
  box.hidden = false;
  clearTimeout(messageTimer);
  messageTimer = setTimeout(() => { box.hidden = true; }, 6000);
}

function send(command) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(command));
}

function updateBar() {
  const seconds = scene ? (tick * scene.dt).toFixed(1) : '0';
  document.getElementById('clock').textContent =
    `tick ${tick}  t = ${seconds} s  ${done ? '(done)' : playing ? '' : '(paused)'}${moved ? ' (moved)' : ''}${scene && scene.replay ? ' (replay)' : ''}`;
  document.getElementById('play').innerHTML = playing ? '&#10074;&#10074; Pause' : '&#9654; Play';
  document.getElementById('play').disabled = done;
  document.getElementById('step').disabled = done;
  document.body.dataset.tick = tick;
  document.title = `Colony: tick ${tick}`;
}

function connect() {
  // The page's query carries the access token, when the server asks for one.
  socket = new WebSocket(`ws://${location.host}/${location.search}`);
  socket.binaryType = 'arraybuffer';
  socket.onmessage = (event) => {
    if (event.data instanceof ArrayBuffer) {
      applyFrame(event.data);
      updateBar();
      refreshInspect();
      return;
    }
    const message = JSON.parse(event.data);
    if (message.type === 'scene') buildScene(message);
    else if (message.type === 'status') {
      tick = message.tick; playing = message.playing; done = message.done; speed = message.speed;
      moved = message.moved;
      if (document.activeElement !== document.getElementById('seed')) {
        document.getElementById('seed').value = String(message.seed);
      }
      document.getElementById('speed').value = String(speed);
      updateBar();
      refreshInspect();
      needsRender = true;
    } else if (message.type === 'rays') {
      allRays = message;
      rebuildOverlays();
    } else if (message.type === 'inspect') {
      inspected = message;
      rebuildOverlays();
      needsRender = true;
    } else if (message.type === 'error') showMessage('the simulator says: ' + message.message);
  };
  socket.onclose = (event) => {
    playing = false;
    document.getElementById('clock').textContent =
      `disconnected (code ${event.code}${event.reason ? ': ' + event.reason : ''})`;
  };
}

document.getElementById('play').onclick = () => send({ cmd: playing ? 'pause' : 'play' });
document.getElementById('step').onclick = () => send({ cmd: 'step' });
document.getElementById('speed').onchange = (e) => {
  const v = e.target.value;
  send({ cmd: 'speed', value: v === 'max' ? 'max' : Number(v) });
};
document.getElementById('reset').onclick = () => {
  const seed = document.getElementById('seed').value;
  send(seed === '' ? { cmd: 'reset' } : { cmd: 'reset', seed: Number(seed) });
};
for (const name of Object.keys(overlays)) {
  const box = document.getElementById('overlay-' + name);
  box.checked = overlays[name];
  box.onchange = () => { overlays[name] = box.checked; allRaysTick = -1; refreshAllRays(); rebuildOverlays(); };
}
document.getElementById('top').onclick = topView;
document.getElementById('persp').onclick = perspectiveView;
document.getElementById('quit').onclick = () => {
  if (confirm('End the served run? The simulator stops serving.')) send({ cmd: 'quit' });
};
window.addEventListener('keydown', (e) => {
  if (e.target.tagName === 'SELECT' || e.target.tagName === 'INPUT') return;
  if (e.key === ' ') { send({ cmd: playing ? 'pause' : 'play' }); e.preventDefault(); }
  else if (e.key === 's') send({ cmd: 'step' });
  else if (e.key === 't') topView();
  else if (e.key === 'p') perspectiveView();
  else if (e.key === 'Escape') { selected = -1; inspected = null; rebuildOverlays(); }
});
// Click: select (and inspect) the robot under the pointer. Shift + drag
// while paused: move a robot or movable object (the simulator checks the
// place; the next frame shows it there, or an error says why not).
let down = null, dragging = -1, dragTo = null;
const floorPlane = new THREE.Plane(new THREE.Vector3(0, 0, 1), 0);
const raycaster = new THREE.Raycaster();
function floorPoint(e, z) {
  const rect = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
                                -(e.clientY - rect.top) / rect.height * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  floorPlane.constant = -z;
  const hit = new THREE.Vector3();
  return raycaster.ray.intersectPlane(floorPlane, hit) ? [hit.x, hit.y] : null;
}
renderer.domElement.addEventListener('pointerdown', (e) => {
  down = [e.clientX, e.clientY];
  if (!e.shiftKey || playing) return;
  const i = pick(e.clientX, e.clientY);
  if (i < 0) return;
  dragging = i;
  dragTo = null;
  selected = i;
  controls.enabled = false;
  renderer.domElement.setPointerCapture(e.pointerId);
  needsRender = true;
});
renderer.domElement.addEventListener('pointermove', (e) => {
  if (dragging < 0) return;
  dragTo = floorPoint(e, movers[dragging].pose[2]);
  needsRender = true;
});
renderer.domElement.addEventListener('pointerup', (e) => {
  if (dragging >= 0) {
    const m = movers[dragging];
    if (dragTo) send({ cmd: 'move', id: m.desc.id, x: dragTo[0], y: dragTo[1] });
    dragging = -1;
    dragTo = null;
    controls.enabled = true;
    needsRender = true;
    return;
  }
  if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
  selected = pick(e.clientX, e.clientY);
  inspected = null;
  askInspect();
  rebuildOverlays();
});
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
  labels.setSize(window.innerWidth, window.innerHeight);
  needsRender = true;
});

// Draws when something changed; records what was drawn for tests.
function animate() {
  requestAnimationFrame(animate);
  if (!needsRender) return;
  needsRender = false;
  showInspect();
  renderer.render(world, camera);
  labels.render(world, camera);
  if (framesApplied) {
    document.body.dataset.drawn = `${drawnCount.points} ${drawnCount.lines} ${drawnCount.circles} ${drawnCount.texts}`;
    document.body.dataset.overlayLines = overlayLines;  // once drawn, with their labels
    document.body.dataset.robotsDrawn = movers.filter((m) => m.desc.robot).length;
    document.body.dataset.moversDrawn = movers.length;
  }
}

// For tests that drive the page through Chromium's DevTools protocol: where
// a mover, or a point of the world, is on the page (CSS pixels from its
// top-left corner), as pick() and floorPoint() see it.
function screenOfPoint(x, y, z) {
  const rect = renderer.domElement.getBoundingClientRect();
  const p = new THREE.Vector3(x, y, z).project(camera);
  return [(p.x + 1) / 2 * rect.width + rect.left, (1 - p.y) / 2 * rect.height + rect.top];
}
window.colonyViewer = {
  screenOfPoint,
  screenOf(id) {
    const m = movers.find((mover) => mover.desc.id === id);
    return m ? screenOfPoint(m.pose[0], m.pose[1], m.pose[2] + m.scale[2] / 2) : null;
  },
};

window.addEventListener('error', (e) => showMessage('viewer error: ' + e.message));
connect();
animate();
