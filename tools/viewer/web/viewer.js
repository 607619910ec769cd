// hadal-viewer's page: a three.js view of the run (seabed, vehicles and their moving links, trails, DVL and
// altimeter beams, light cones, camera frusta), camera panes, plots and the status line, fed by hadal-viewer
// over a WebSocket (tools/viewer/viewer_state.h says what it sends). World frame W is ENU with z up, as on the
// wire; three.js's camera is told that z is up, so nothing is converted. window.hadalViewer exposes what
// is drawn, for tests and the curious.
'use strict';

const PLOT_WINDOW_S = 60;      // sim seconds a plot shows
const MAX_TRAIL = 20000;       // points per trail (as the server keeps)
const MAX_SERIES = 3000;       // points per series (as the server keeps)
const PALETTE = ['#7fd1ff', '#ffc46b', '#9be08b', '#ff8a7a', '#c9a0ff', '#f5f57a'];

const state = {
  scene: null,            // the scene JSON
  meshes: [],             // THREE.Mesh per scene mesh (index as in the scene)
  vehicles: {},           // name -> {group, trail, trailCount, lastUpdate}
  frames: {},             // "vehicle/name" -> {frame JSON, object}
  links: {},              // "vehicle/link" -> {link JSON, moving: THREE.Group} (articulated vehicles' moving bodies)
  overlays: {},           // "vehicle/sensor" -> THREE.LineSegments
  acoustic: null,         // THREE.LineSegments of the acoustic signals in flight
  acousticLinks: [],      // the last AcousticLinks' links, as drawn
  acousticFronts: null,   // THREE.Points: each signal's front
  paths: {},              // a cable's shape topic -> THREE.Line
  surface: null,          // the sea surface in a scene with waves: {mesh, components, ramp, time, centre}
  series: {},             // key -> {plot, label, unit, t: [], v: []}
  historySeq: 0,
  cameras: {},            // topic -> {img, caption, frames, url}
  followed: null,
  updates: 0,
  scenes: 0,              // scene messages taken (first.js and the WebSocket's)
  lastUpdate: null,
  connected: false,       // the WebSocket is open
  firstState: false,      // showing first.js's state, the WebSocket not yet closed once
  source: null,
};

// --- three.js scene ---------------------------------------------------------------------------------
const container = document.getElementById('view3d');
const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(window.devicePixelRatio || 1);
container.appendChild(renderer.domElement);
const scene3 = new THREE.Scene();
scene3.background = new THREE.Color(0x041420);
scene3.fog = new THREE.Fog(0x041420, 60, 450);
const camera = new THREE.PerspectiveCamera(55, 1, 0.05, 5000);
camera.up.set(0, 0, 1);
camera.position.set(-12, -12, 8);
const controls = new THREE.OrbitControls(camera, renderer.domElement);
controls.enableDamping = false;
scene3.add(new THREE.HemisphereLight(0xbfdfff, 0x202830, 0.9));
const sun = new THREE.DirectionalLight(0xffffff, 0.6);
sun.position.set(0.3, -0.4, 1);
scene3.add(sun);
const world = new THREE.Group();  // W
scene3.add(world);

function resize() {
  const w = container.clientWidth, h = container.clientHeight;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = w + 'px';
  renderer.domElement.style.height = h + 'px';
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

function poseObject(object, p, q) {
  object.position.set(p[0], p[1], p[2]);
  object.quaternion.set(q[0], q[1], q[2], q[3]);
}

function clearWorld() {
  world.traverse((o) => {  // free the GPU's copies: a new scene or a reconnect builds everything again
    if (o.geometry) o.geometry.dispose();
    if (o.material) o.material.dispose();
  });
  while (world.children.length) world.remove(world.children[0]);
  state.meshes = [];
  state.vehicles = {};
  state.frames = {};
  state.links = {};
  state.overlays = {};
  state.surface = null;
}

// A light's cone or a camera's frustum in its frame F (x_F forward for a light, z_C forward for a camera).
function frameMarker(frame) {
  if (frame.kind === 'light') {
    const reach = frame.range, radius = reach * Math.tan(frame.half_angle);
    const geometry = new THREE.ConeGeometry(radius, reach, 32, 1, true);
    geometry.translate(0, -reach / 2, 0);  // apex at the origin, opening along -y ...
    geometry.rotateZ(Math.PI / 2);          // ... now along +x
    const material = new THREE.MeshBasicMaterial({color: 0xfff2a8, transparent: true, opacity: 0.07,
                                                  depthWrite: false, side: THREE.DoubleSide});
    const cone = new THREE.Mesh(geometry, material);
    cone.userData.kind = 'light';
    return cone;
  }
  if (frame.kind === 'camera') {
    const d = 1.0, x = d * Math.tan(frame.half_angle), y = 0.75 * x;
    const corners = [[x, y, d], [-x, y, d], [-x, -y, d], [x, -y, d]];
    const points = [];
    for (let i = 0; i < 4; ++i) {
      points.push(0, 0, 0, ...corners[i]);
      points.push(...corners[i], ...corners[(i + 1) % 4]);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
    const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({color: 0x7fd1ff}));
    lines.userData.kind = 'camera';
    return lines;
  }
  return null;
}

function onScene(msg) {
  state.scenes++;
  clearWorld();
  state.scene = msg;
  document.getElementById('scenario').textContent = msg.scenario;
  for (const v of msg.vehicles) {
    const group = new THREE.Group();
    group.name = v.name;
    group.visible = false;  // until its first pose
    world.add(group);
    const trailGeometry = new THREE.BufferGeometry();
    trailGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * MAX_TRAIL), 3));
    trailGeometry.setDrawRange(0, 0);
    const trail = new THREE.Line(trailGeometry, new THREE.LineBasicMaterial({color: 0xffc46b}));
    trail.frustumCulled = false;
    world.add(trail);
    state.vehicles[v.name] = {group, trail, trailCount: 0, trailTotal: 0, last: null};
  }
  // Each moving body of an articulated vehicle: a group at its frame K with the joint at zero (in its
  // parent's, so a body follows its parents), and in it the joint's motion, which holds the body's mesh.
  for (const l of msg.links || []) {
    const vehicle = state.vehicles[l.vehicle];
    const parent = l.parent === 'base_link' ? vehicle && vehicle.group
                                            : (state.links[l.vehicle + '/' + l.parent] || {}).moving;
    if (!parent) continue;
    const fixed = new THREE.Group();
    poseObject(fixed, l.p, l.q);
    const moving = new THREE.Group();
    moving.name = l.vehicle + '/' + l.name;
    fixed.add(moving);
    parent.add(fixed);
    state.links[l.vehicle + '/' + l.name] = {link: l, moving, axis: new THREE.Vector3(...l.axis)};
  }
  for (const f of msg.frames) {
    const object = new THREE.Group();
    const marker = frameMarker(f);
    if (marker) object.add(marker);
    const vehicle = state.vehicles[f.vehicle], link = f.link && state.links[f.vehicle + '/' + f.link];
    if (link) {  // on a moving body: moves with it
      poseObject(object, f.link_p, f.link_q);
      link.moving.add(object);
    } else {
      poseObject(object, f.p, f.q);
      if (vehicle) vehicle.group.add(object);
    }
    state.frames[f.vehicle + '/' + f.name] = {frame: f, object};
  }
  const follow = document.getElementById('follow');
  follow.innerHTML = '';
  for (const v of msg.vehicles) follow.add(new Option(v.name + ' (' + v.type + ')', v.name));
  state.followed = msg.vehicles.length ? msg.vehicles[0].name : null;
  state.surface = makeSurface(msg);
  if (state.surface) world.add(state.surface.mesh);
  rebuildPlots();
  applyToggles();
}

// The sea surface (a scene with waves): a grid of SURFACE_CELLS^2 cells of SURFACE_SIDE metres around the followed
// vehicle, its heights eta(x, y, t) = r(t) sum a cos(k (x cos b + y sin b) - w t + phi) from the scene's components at
// the latest sim time (physics/waves.h, hadal_msgs/Scene), recomputed when the time changes.
const SURFACE_CELLS = 48, SURFACE_SIDE = 120;
function makeSurface(msg) {
  if (!msg.waves) return null;
  const n = SURFACE_CELLS + 1;
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * n * n), 3));
  const indices = [];
  for (let j = 0; j < SURFACE_CELLS; ++j) {
    for (let i = 0; i < SURFACE_CELLS; ++i) {
      const a = j * n + i;
      indices.push(a, a + 1, a + n + 1, a, a + n + 1, a + n);
    }
  }
  geometry.setIndex(indices);
  const material = new THREE.MeshLambertMaterial({color: 0x2f8fc8, transparent: true, opacity: 0.5,
                                                  side: THREE.DoubleSide, depthWrite: false});
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = 'sea surface';
  mesh.frustumCulled = false;
  mesh.renderOrder = 1;
  const components = msg.waves.components.map(([a, w, k, b, phi]) => [a, w, k * Math.cos(b), k * Math.sin(b), phi]);
  return {mesh, components, ramp: msg.waves.ramp_time, time: null, centre: null};
}

function updateSurface(t, centre) {
  const s = state.surface;
  if (!s || t === null) return;
  const step = SURFACE_SIDE / SURFACE_CELLS;
  const cx = Math.round(centre[0] / step) * step, cy = Math.round(centre[1] / step) * step;  // the grid stays put
  if (s.time === t && s.centre && s.centre[0] === cx && s.centre[1] === cy) return;
  s.time = t;
  s.centre = [cx, cy];
  const r = t >= s.ramp ? 1.0 : (t <= 0.0 ? 0.0 : 0.5 * (1.0 - Math.cos(Math.PI * t / s.ramp)));
  const n = SURFACE_CELLS + 1, z0 = state.scene.water_surface_z;
  const positions = s.mesh.geometry.attributes.position.array;
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      const x = cx + (i - SURFACE_CELLS / 2) * step, y = cy + (j - SURFACE_CELLS / 2) * step;
      let eta = 0.0;
      for (const [a, w, kx, ky, phi] of s.components) eta += a * Math.cos(kx * x + ky * y - w * t + phi);
      const o = 3 * (j * n + i);
      positions[o] = x;
      positions[o + 1] = y;
      positions[o + 2] = z0 + r * eta;
    }
  }
  s.mesh.geometry.attributes.position.needsUpdate = true;
  s.mesh.geometry.computeVertexNormals();
}

function onMesh(index, positions, indices) {
  const info = state.scene && state.scene.meshes[index];
  if (!info) return;
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeVertexNormals();
  const c = info.color.map((x) => Math.min(1, 1.6 * x));
  let material;
  if (info.name === 'seabed') {
    // Shade by height so relief reads at a glance: darker in the hollows.
    let zmin = Infinity, zmax = -Infinity;
    for (let i = 2; i < positions.length; i += 3) {
      zmin = Math.min(zmin, positions[i]);
      zmax = Math.max(zmax, positions[i]);
    }
    const colors = new Float32Array(positions.length);
    for (let i = 0; i < positions.length; i += 3) {
      const s = 0.55 + 0.45 * (zmax > zmin ? (positions[i + 2] - zmin) / (zmax - zmin) : 1);
      colors[i] = c[0] * s; colors[i + 1] = c[1] * s; colors[i + 2] = c[2] * s;
    }
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    material = new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors, side: THREE.DoubleSide});
  } else {
    material = new THREE.MeshLambertMaterial({color: new THREE.Color(c[0], c[1], c[2])});
  }
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = info.name;
  state.meshes[index] = mesh;
  const vehicle = state.vehicles[info.name], link = state.links[info.name];
  (vehicle ? vehicle.group : link ? link.moving : world).add(mesh);
}

// DVL beams and altimeter ranges, in the sensor's frame: green where the beam returned, grey (to the
// sensor's reach) where it did not.
function updateOverlay(o) {
  const key = o.vehicle + '/' + o.sensor;
  const frame = state.frames[key];
  if (!frame) return;
  let lines = state.overlays[key];
  if (!lines) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * 2 * 4), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * 2 * 4), 3));
    lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors}));
    lines.frustumCulled = false;
    lines.userData.kind = 'beam';
    frame.object.add(lines);
    state.overlays[key] = lines;
  }
  const beams = o.kind === 'dvl' ? o.beams : [[1, 0, 0, o.range]];
  const reach = o.kind === 'dvl' ? frame.frame.range : (o.max_range || frame.frame.range);
  const pos = lines.geometry.attributes.position, col = lines.geometry.attributes.color;
  beams.forEach((b, i) => {
    const hit = b[3] !== null && isFinite(b[3]);
    const r = hit ? b[3] : reach;
    pos.setXYZ(2 * i, 0, 0, 0);
    pos.setXYZ(2 * i + 1, b[0] * r, b[1] * r, b[2] * r);
    const c = hit ? [0.45, 1.0, 0.45] : [0.35, 0.4, 0.45];
    col.setXYZ(2 * i, ...c);
    col.setXYZ(2 * i + 1, ...c);
  });
  lines.geometry.setDrawRange(0, 2 * beams.length);
  pos.needsUpdate = true;
  col.needsUpdate = true;
}

// Acoustic signals in flight (rt/hadal/acoustic_links): for each, its straight path from where it left to its
// receiver, dim, and on it, bright, what of it is in the water at the links' sim time: a packet from its tail to
// its front (sound speed x (t - emit) and that less the packet's duration), a ping from where it left to its
// front. Orange: modem packets; cyan: interrogations; magenta: replies. Not fogged: they span kilometres.
const ACOUSTIC_COLORS = [[1.0, 0.62, 0.2], [0.3, 0.9, 1.0], [1.0, 0.4, 0.9]];
function updateAcoustic(acoustic) {
  const links = acoustic ? acoustic.links : [];
  state.acousticLinks = links;
  if (!state.acoustic) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * 4 * 256), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * 4 * 256), 3));
    state.acoustic = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors, fog: false}));
    state.acoustic.frustumCulled = false;
    state.acoustic.userData.kind = 'acoustic';
    world.add(state.acoustic);
    const fronts = new THREE.BufferGeometry();  // a dot at each wavefront, visible from kilometres away
    fronts.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * 256), 3));
    fronts.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * 256), 3));
    state.acousticFronts = new THREE.Points(fronts, new THREE.PointsMaterial(
        {size: 7, sizeAttenuation: false, vertexColors: THREE.VertexColors, fog: false}));
    state.acousticFronts.frustumCulled = false;
    world.add(state.acousticFronts);
  }
  const dots = state.acousticFronts.geometry.attributes.position, dotColors = state.acousticFronts.geometry.attributes.color;
  let m = 0;
  const pos = state.acoustic.geometry.attributes.position, col = state.acoustic.geometry.attributes.color;
  let n = 0;
  for (const [kind, v, , ] of links.slice(0, 256)) {
    const o = new THREE.Vector3(v[0], v[1], v[2]), p = new THREE.Vector3(v[3], v[4], v[5]);
    const length = p.distanceTo(o);
    if (!(length > 0)) continue;
    const u = p.clone().sub(o).divideScalar(length);
    const elapsed = acoustic.time - v[6];
    const front = Math.min(v[8] * elapsed, length), tail = Math.max(v[8] * (elapsed - v[7]), 0);
    const c = ACOUSTIC_COLORS[kind] || ACOUSTIC_COLORS[0];
    const ends = [[o, p, c.map(x => 0.3 * x)],
                  [o.clone().addScaledVector(u, v[7] > 0 ? Math.min(tail, front) : 0), o.clone().addScaledVector(u, front), c]];
    for (const [a, b, color] of ends) {
      pos.setXYZ(n, a.x, a.y, a.z); col.setXYZ(n++, ...color);
      pos.setXYZ(n, b.x, b.y, b.z); col.setXYZ(n++, ...color);
    }
    const front3 = ends[1][1];
    dots.setXYZ(m, front3.x, front3.y, front3.z); dotColors.setXYZ(m++, ...c);
  }
  state.acousticFronts.geometry.setDrawRange(0, m);
  dots.needsUpdate = true;
  dotColors.needsUpdate = true;
  state.acoustic.geometry.setDrawRange(0, n);
  pos.needsUpdate = true;
  col.needsUpdate = true;
}

// A cable's shape (nav_msgs/Path of its nodes in W): a yellow line, not fogged (cables run for hundreds of metres).
function updatePath(topic, points) {
  let line = state.paths[topic];
  const n = points.length / 3;
  if (!line || line.geometry.attributes.position.count < n) {
    if (line) world.remove(line);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * Math.max(n, 2)), 3));
    line = new THREE.Line(geometry, new THREE.LineBasicMaterial({color: 0xffd54a, fog: false}));
    line.frustumCulled = false;
    line.userData.kind = 'cable';
    world.add(line);
    state.paths[topic] = line;
  }
  line.geometry.attributes.position.array.set(points);
  line.geometry.attributes.position.needsUpdate = true;
  line.geometry.setDrawRange(0, n);
}

// One trail point (the server keeps them 5 cm apart, viewer_state.cc).
function appendTrail(vehicle, p) {
  const attr = vehicle.trail.geometry.attributes.position;
  if (vehicle.trailCount >= MAX_TRAIL) {  // drop the oldest tenth
    const keep = MAX_TRAIL - MAX_TRAIL / 10;
    attr.array.copyWithin(0, 3 * (MAX_TRAIL / 10), 3 * MAX_TRAIL);
    vehicle.trailCount = keep;
  }
  attr.setXYZ(vehicle.trailCount++, p[0], p[1], p[2]);
  attr.needsUpdate = true;
  vehicle.trail.geometry.setDrawRange(0, vehicle.trailCount);
  vehicle.trailTotal++;
}

// Trail points [x, y, z, ...] whose first has index `from` among all the vehicle's points; those the page
// has already are skipped.
function appendTrailPoints(vehicle, from, points) {
  for (let i = 0; i + 2 < points.length; i += 3) {
    if (from + i / 3 >= vehicle.trailTotal) appendTrail(vehicle, [points[i], points[i + 1], points[i + 2]]);
  }
}

function onHistory(msg) {
  state.historySeq = msg.seq;
  for (const [name, vehicle] of Object.entries(state.vehicles)) {
    const trail = msg.trails[name] || {total: 0, points: []};
    vehicle.trailCount = 0;
    vehicle.trailTotal = trail.total - trail.points.length / 3;
    appendTrailPoints(vehicle, vehicle.trailTotal, trail.points);
    vehicle.trail.geometry.setDrawRange(0, vehicle.trailCount);
  }
  state.series = {};
  for (const [key, s] of Object.entries(msg.series)) {
    state.series[key] = {plot: s.plot, label: s.label, unit: s.unit, t: s.t, v: s.v};
  }
  rebuildPlots();
}

// The vehicle's moving bodies at its joints' positions (rt/<vehicle>/joint_states): a rotation about the
// joint's axis, or a translation along it.
function poseLinks(vehicleName, joints) {
  for (const link of Object.values(state.links)) {
    if (link.link.vehicle !== vehicleName || !(link.link.joint in joints)) continue;
    const q = joints[link.link.joint];
    if (link.link.joint_type === 'prismatic') {
      link.moving.position.copy(link.axis).multiplyScalar(q);
    } else {
      link.moving.quaternion.setFromAxisAngle(link.axis, q);
    }
  }
}

function onUpdate(msg) {
  state.updates++;
  state.lastUpdate = msg;
  state.source = msg.source;
  for (const [name, v] of Object.entries(msg.vehicles)) {
    const vehicle = state.vehicles[name];
    if (!vehicle) continue;
    const previous = vehicle.group.position.clone();
    poseObject(vehicle.group, v.p, v.q);
    vehicle.group.visible = true;
    if (v.joints) poseLinks(name, v.joints);
    vehicle.last = v;
    appendTrailPoints(vehicle, v.trail_from, v.trail);
    if (name === state.followed) {  // the orbit follows the vehicle
      const delta = vehicle.group.position.clone().sub(previous);
      if (!vehicle.followed) {
        controls.target.copy(vehicle.group.position);
        camera.position.copy(vehicle.group.position).add(new THREE.Vector3(-10, -10, 6));
        vehicle.followed = true;
      } else {
        controls.target.add(delta);
        camera.position.add(delta);
      }
    }
  }
  if (state.surface) {  // the sea at the latest pose's time, around the followed vehicle
    let t = null;
    for (const v of Object.values(msg.vehicles)) if (t === null || v.stamp > t) t = v.stamp;
    const followed = state.vehicles[state.followed];
    updateSurface(t, followed && followed.last ? followed.last.p : [0, 0]);
  }
  for (const o of msg.overlays) updateOverlay(o);
  updateAcoustic(msg.acoustic);
  for (const [topic, points] of Object.entries(msg.paths || {})) updatePath(topic, points);
  let newSeries = false;
  for (const p of msg.points) {
    const [key, seq, t, v] = p;
    if (seq <= state.historySeq) continue;
    let s = state.series[key];
    if (!s) {
      const info = msg.series[key];
      s = state.series[key] = {plot: info.plot, label: info.label, unit: info.unit, t: [], v: []};
      newSeries = true;
    }
    s.t.push(t);
    s.v.push(v);
    if (s.t.length > MAX_SERIES) { s.t.shift(); s.v.shift(); }
  }
  if (newSeries) rebuildPlots();
  for (const [topic, c] of Object.entries(msg.cameras)) {
    const pane = cameraPane(topic);
    pane.info = c;
    pane.figure.hidden = !['rgb8', 'mono8', 'bgr8'].includes(c.encoding);  // depth images: listed in the status only
    pane.caption.textContent = topic + ' · ' + c.width + '×' + c.height + ' ' + c.encoding +
        ' · t = ' + c.stamp.toFixed(2) + ' s · ' + c.frames + ' frames';
  }
  renderStatus(msg);
  renderSource(msg.source);
}

// --- camera panes -------------------------------------------------------------------------------------
function cameraPane(topic) {
  let pane = state.cameras[topic];
  if (!pane) {
    const figure = document.createElement('figure');
    const img = document.createElement('img');
    img.alt = topic;
    const caption = document.createElement('figcaption');
    caption.textContent = topic;
    figure.append(img, caption);
    document.getElementById('cameras').append(figure);
    pane = state.cameras[topic] = {figure, img, caption, shown: 0, url: null, info: null};
  }
  return pane;
}

function onJpeg(topic, bytes) {
  const pane = cameraPane(topic);
  const url = URL.createObjectURL(new Blob([bytes], {type: 'image/jpeg'}));
  const old = pane.url;
  pane.url = url;
  pane.img.onload = () => { if (old) URL.revokeObjectURL(old); pane.shown++; };
  pane.img.onerror = () => { if (old) URL.revokeObjectURL(old); };
  pane.img.src = url;
}

// --- plots ----------------------------------------------------------------------------------------------
let plotCanvases = {};
function rebuildPlots() {
  const section = document.getElementById('plots');
  section.innerHTML = '';
  plotCanvases = {};
  const groups = [...new Set(Object.values(state.series).map((s) => s.plot))]
      .filter((g) => !state.followed || g.startsWith(state.followed + ' ')).sort();
  for (const g of groups) {
    const title = document.createElement('div');
    title.className = 'plot-title';
    title.textContent = g;
    const canvas = document.createElement('canvas');
    canvas.className = 'plot';
    section.append(title, canvas);
    plotCanvases[g] = canvas;
  }
}

function drawPlots() {
  const now = state.lastUpdate ? state.lastUpdate.sim_time : 0;
  for (const [group, canvas] of Object.entries(plotCanvases)) {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== w) canvas.width = w;
    if (canvas.height !== h) canvas.height = h;
    const ctx = canvas.getContext('2d');
    ctx.clearRect(0, 0, w, h);
    const series = Object.values(state.series).filter((s) => s.plot === group);
    // The last PLOT_WINDOW_S seconds, or from the first point on early in a run (an axis of at least 5 s).
    const first = Math.min(...series.map((s) => (s.t.length ? s.t[0] : now)));
    const t0 = now - Math.min(PLOT_WINDOW_S, now - first);
    const span = Math.max(5, now - t0);
    let lo = Infinity, hi = -Infinity;
    for (const s of series) {
      for (let i = 0; i < s.t.length; ++i) {
        if (s.t[i] < t0 || s.v[i] === null) continue;
        lo = Math.min(lo, s.v[i]); hi = Math.max(hi, s.v[i]);
      }
    }
    if (!(hi >= lo)) continue;
    if (hi - lo < 1e-6) { hi += 0.5; lo -= 0.5; }
    const pad = 0.08 * (hi - lo); lo -= pad; hi += pad;
    const x = (t) => 44 + (w - 50) * (t - t0) / span;
    const y = (v) => h - 14 - (h - 20) * (v - lo) / (hi - lo);
    ctx.strokeStyle = '#1d3850'; ctx.fillStyle = '#8fb3cc'; ctx.font = '10px sans-serif';
    ctx.beginPath(); ctx.moveTo(44, 4); ctx.lineTo(44, h - 14); ctx.lineTo(w - 6, h - 14); ctx.stroke();
    ctx.fillText(hi.toPrecision(4), 2, 12); ctx.fillText(lo.toPrecision(4), 2, h - 16);
    ctx.fillText(t0.toFixed(1) + ' s', 46, h - 3); ctx.fillText((t0 + span).toFixed(1) + ' s', w - 50, h - 3);
    let legendX = 50;
    series.forEach((s, k) => {
      ctx.strokeStyle = PALETTE[k % PALETTE.length];
      ctx.beginPath();
      let pen = false;
      for (let i = 0; i < s.t.length; ++i) {
        if (s.t[i] < t0 || s.v[i] === null) { pen = false; continue; }
        if (pen) ctx.lineTo(x(s.t[i]), y(s.v[i])); else ctx.moveTo(x(s.t[i]), y(s.v[i]));
        pen = true;
      }
      ctx.stroke();
      const last = s.v.length ? s.v[s.v.length - 1] : null;
      const text = s.label + ' ' + (last === null ? '–' : last.toFixed(2)) + ' ' + s.unit;
      ctx.fillStyle = PALETTE[k % PALETTE.length];
      ctx.fillText(text, legendX, 12);
      legendX += ctx.measureText(text).width + 12;
    });
  }
}

// --- status line and bag controls --------------------------------------------------------------------
function renderStatus(msg) {
  const s = msg.status;
  const el = document.getElementById('status');
  if (!s) {
    el.textContent = 'sim ' + msg.sim_time.toFixed(2) + ' s · no status yet';
    return;
  }
  const faults = Object.entries(s.faults).filter(([, bits]) => bits).map(([name, bits]) => name + ' ' + bits);
  el.innerHTML = '';
  const parts = ['sim ' + s.sim_time.toFixed(2) + ' s', 'RTF ' + (s.rtf || 0).toFixed(2), s.mode,
                 s.steps + ' steps'];
  el.append(parts.join(' · ') + ' · ');
  const faultSpan = document.createElement('span');
  faultSpan.textContent = faults.length ? 'faults: ' + faults.join(', ') : 'no faults';
  if (faults.length) faultSpan.className = 'fault';
  el.append(faultSpan);
  const rejected = document.createElement('span');
  rejected.textContent = ' · rejected ' + s.rejected_commands + (s.last_error ? ' (' + s.last_error + ')' : '');
  if (s.rejected_commands) rejected.className = 'fault';
  el.append(rejected, ' · dropped ' + s.dropped_captures);
}

function renderSource(source) {
  const el = document.getElementById('source');
  el.innerHTML = '';
  const dot = document.createElement('span');
  if (!source) return;
  const linked = state.connected || state.firstState;
  if (source.kind === 'live') {
    const up = linked && source.connected;
    dot.className = up ? 'up' : 'down';
    dot.textContent = up ? '● live' : '○ waiting for hadald';
    el.append(dot, ' · domain ' + source.domain);
    return;
  }
  dot.className = linked ? 'up' : 'down';
  dot.textContent = linked ? '● bag' : '○ bag';
  el.append(dot, ' ' + source.path.replace(/\/+$/, '').split('/').pop());
  el.title = source.path;
  const bar = document.getElementById('bagbar');
  bar.hidden = false;
  const timeline = document.getElementById('timeline');
  timeline.max = source.duration;
  if (!timeline.matches(':active')) timeline.value = source.t;
  document.getElementById('bagtime').textContent = source.t.toFixed(2) + ' / ' + source.duration.toFixed(2) + ' s';
  document.getElementById('play').textContent = source.playing ? '❚❚' : '▶';
}

// --- connection -------------------------------------------------------------------------------------------
let socket = null;
let sceneIdHeld = null;  // the scene first.js brought: the first WebSocket join need not send it again
function send(command) { if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(command)); }

function onText(msg) {
  if (msg.type === 'scene') onScene(msg);
  else if (msg.type === 'history') onHistory(msg);
  else if (msg.type === 'update') onUpdate(msg);
}

function onBinary(buffer) {
  const view = new DataView(buffer);
  const tag = String.fromCharCode(view.getUint8(0), view.getUint8(1), view.getUint8(2), view.getUint8(3));
  const nameLength = view.getUint32(4, true);
  const name = new TextDecoder().decode(new Uint8Array(buffer, 8, nameLength));
  const offset = 8 + nameLength + ((4 - (nameLength % 4)) % 4);
  if (tag === 'MESH') {
    const floats = view.getUint32(offset, true), indices = view.getUint32(offset + 4, true);
    onMesh(Number(name), new Float32Array(buffer, offset + 8, floats),
           new Uint32Array(buffer, offset + 8 + 4 * floats, indices));
  } else if (tag === 'JPEG') {
    onJpeg(name, new Uint8Array(buffer, offset));
  }
}

// The page's first state (first.js, loaded before this script: hadal-viewer serves it once it has what a first
// paint shows): the messages a WebSocket join sends, binary ones in base64. Drawn at once, so the page shows
// the run at its load event (and a one-shot screenshot does too).
function applyFirst(first) {
  const bytes = (b64) => Uint8Array.from(atob(b64), (c) => c.charCodeAt(0)).buffer;
  state.firstState = true;
  if (first.scene) {
    onScene(first.scene);
    for (const mesh of first.meshes) onBinary(bytes(mesh));
    sceneIdHeld = first.scene_id;
  }
  onHistory(first.history);
  for (const image of first.images) onBinary(bytes(image));
  onUpdate(first.update);
  controls.update();
  renderer.render(scene3, camera);
}

function connect() {
  const url = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws' +
      (sceneIdHeld ? '?scene=' + encodeURIComponent(sceneIdHeld) : '');
  sceneIdHeld = null;  // a reconnect (to a viewer perhaps restarted) is sent everything
  socket = new WebSocket(url);
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => { state.connected = true; };
  socket.onclose = () => {
    state.connected = false;
    state.firstState = false;
    renderSource(state.source);
    setTimeout(connect, 1000);
  };
  socket.onmessage = (event) => {
    if (typeof event.data !== 'string') { onBinary(event.data); return; }
    onText(JSON.parse(event.data));
  };
}

function applyToggles() {
  const trails = document.getElementById('show-trails').checked;
  const beams = document.getElementById('show-beams').checked;
  const lights = document.getElementById('show-lights').checked;
  for (const v of Object.values(state.vehicles)) v.trail.visible = trails;
  world.traverse((o) => {
    if (o.userData.kind === 'beam') o.visible = beams;
    if (o.userData.kind === 'light') o.visible = lights;
  });
}

document.getElementById('follow').addEventListener('change', (e) => {
  state.followed = e.target.value;
  const v = state.vehicles[state.followed];
  if (v) v.followed = false;
  rebuildPlots();
});
for (const id of ['show-trails', 'show-beams', 'show-lights']) {
  document.getElementById(id).addEventListener('change', applyToggles);
}
document.getElementById('play').addEventListener('click', () => {
  send({cmd: state.source && state.source.playing ? 'pause' : 'play'});
});
document.getElementById('timeline').addEventListener('input', (e) => send({cmd: 'seek', t: Number(e.target.value)}));
document.getElementById('speed').addEventListener('change', (e) => send({cmd: 'speed', x: Number(e.target.value)}));

let lastPlot = 0;
function animate(time) {
  requestAnimationFrame(animate);
  const size = renderer.getSize(new THREE.Vector2());
  if (container.clientWidth !== size.x || container.clientHeight !== size.y) resize();
  controls.update();
  renderer.render(scene3, camera);
  if (time - lastPlot > 200) { drawPlots(); lastPlot = time; }
}

// The RGBA bytes of an image or a canvas (width x height), drawn into a 2-D canvas to read them.
function pixelsOf(source, width, height) {
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  const ctx = canvas.getContext('2d');
  ctx.drawImage(source, 0, 0);
  return ctx.getImageData(0, 0, width, height).data;
}

// What is drawn, for tests: a vehicle's pose as the 3-D view has it, and a camera pane's mean pixel value.
window.hadalViewer = {
  state,
  // The sea surface's middle vertex as drawn (W, float32) and the sim time it is drawn for; null without waves.
  seaSurface() {
    const s = state.surface;
    if (!s || s.time === null) return null;
    const n = SURFACE_CELLS + 1, o = 3 * ((SURFACE_CELLS / 2) * n + SURFACE_CELLS / 2);
    const a = s.mesh.geometry.attributes.position.array;
    return {time: s.time, p: [a[o], a[o + 1], a[o + 2]], vertices: n * n};
  },
  vehiclePose(name) {
    const v = state.vehicles[name];
    if (!v || !v.group.visible) return null;
    const p = v.group.position, q = v.group.quaternion;
    // The camera may have moved (following the vehicle) since the last frame rendered its matrices: a
    // test asking between the two would see the vehicle where the old view had it.
    camera.updateMatrixWorld();
    const ndc = p.clone().project(camera);  // inside the view: normalised device coordinates in [-1, 1]
    const onScreen = Math.abs(ndc.x) <= 1 && Math.abs(ndc.y) <= 1 && ndc.z >= -1 && ndc.z <= 1;
    return {p: [p.x, p.y, p.z], q: [q.x, q.y, q.z, q.w], stamp: v.last.stamp, on_screen: onScreen,
            meshes: v.group.children.filter((c) => c.isMesh).length};
  },
  // A moving body: its pose in W (three.js's world, the scene's W) and its mesh's vertex count (0 without a
  // mesh); null when the scene has no such body.
  linkPose(vehicle, link) {
    const l = state.links[vehicle + '/' + link];
    if (!l) return null;
    const mesh = l.moving.children.find((c) => c.isMesh);
    l.moving.updateMatrixWorld(true);
    const p = new THREE.Vector3(), q = new THREE.Quaternion();
    l.moving.getWorldPosition(p);
    l.moving.getWorldQuaternion(q);
    return {p: [p.x, p.y, p.z], q: [q.x, q.y, q.z, q.w], vertices: mesh ? mesh.geometry.attributes.position.count : 0};
  },
  cameraMean(topic) {
    const pane = state.cameras[topic];
    if (!pane || !pane.shown || !pane.img.naturalWidth) return null;
    const width = pane.img.naturalWidth, height = pane.img.naturalHeight;
    const data = pixelsOf(pane.img, width, height);
    let sum = 0;
    for (let i = 0; i < data.length; i += 4) sum += data[i] + data[i + 1] + data[i + 2];
    return {mean: sum / (3 * data.length / 4), width, height, shown: pane.shown};
  },
  seabedTriangles() { return state.meshes[0] ? state.meshes[0].geometry.index.count / 3 : 0; },
  // The share of the 3-D view's pixels that are not the background: > 0 once something is drawn.
  drawnFraction() {
    const source = renderer.domElement;
    const data = pixelsOf(source, source.width, source.height);
    const bg = scene3.background;
    const background = [bg.r * 255, bg.g * 255, bg.b * 255];
    let drawn = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - background[0]) + Math.abs(data[i + 1] - background[1]) +
          Math.abs(data[i + 2] - background[2]) > 12) drawn++;
    }
    return drawn / (data.length / 4);
  },
  atLoad: null,  // what the page showed at its load event (set then)
};

// What the page showed at its load event, when a one-shot screenshot is taken: for tests.
window.addEventListener('load', () => {
  const cameras = {};
  for (const topic of Object.keys(state.cameras)) cameras[topic] = window.hadalViewer.cameraMean(topic);
  const poses = {};
  for (const name of Object.keys(state.vehicles)) poses[name] = window.hadalViewer.vehiclePose(name);
  window.hadalViewer.atLoad = {
    seabed_triangles: window.hadalViewer.seabedTriangles(), poses, cameras,
    status: document.getElementById('status').textContent, drawn: window.hadalViewer.drawnFraction(),
  };
});

if (window.hadalFirst) applyFirst(window.hadalFirst);
connect();
requestAnimationFrame(animate);
