// Physics view: the MuJoCo world drawn with three.js (global THREE, Debian's libjs-three r111)
// from `physics.scene`, its joints from `physics`, sliders that move servo-driven joints with
// `hand.move`, and pushes with `physics.apply`.
import * as api from './api.js';
import * as servos from './servos.js';
import {$, el, fillSelect, fmt, num, setText, showMessage} from './util.js';

const kRadToDeg = 180 / Math.PI;
let context = null;
let available = false;
let visible = false;
let view3d = null;      // {renderer, scene, camera, controls, geoms: [Object3D], signature}
let jointsSignature = '';
let polls = 0;
let hands = new Map();  // "port/servo" -> hand value (deg)
const sliders = new Map(); // joint name -> {busy, queued, holdUntil}

function colourOf(rgba) {
  const [r, g, b] = Array.isArray(rgba) ? rgba : [0.5, 0.5, 0.5];
  return new THREE.Color(r, g, b);
}

/** A three.js object for one geom, its geometry in the geom's own frame (MuJoCo: capsules
 *  and cylinders along local z; three.js builds them along y, hence the quarter turn). */
function makeGeom(geom, extent) {
  const rgba = Array.isArray(geom.rgba) ? geom.rgba : [0.5, 0.5, 0.5, 1];
  const material = new THREE.MeshStandardMaterial({
    color: colourOf(rgba), roughness: 0.7, metalness: 0.1,
    transparent: rgba[3] < 1, opacity: rgba[3] ?? 1,
  });
  const size = geom.size ?? [0.01, 0.01, 0.01];
  let object;
  switch (geom.type) {
    case 'plane': {
      const hx = size[0] > 0 ? size[0] : extent;
      const hy = size[1] > 0 ? size[1] : extent;
      object = new THREE.Group();
      const plane = new THREE.Mesh(new THREE.PlaneBufferGeometry(2 * hx, 2 * hy), material);
      plane.receiveShadow = true;
      object.add(plane);
      const grid = new THREE.GridHelper(2 * Math.max(hx, hy), Math.max(2, Math.round(Math.max(hx, hy) / Math.max(size[2] || 0.1, 0.05))) , 0x888888, 0xbbbbbb);
      grid.rotation.x = Math.PI / 2;   // GridHelper lies in x-z; MuJoCo's planes lie in x-y
      grid.position.z = 0.0005;
      object.add(grid);
      break;
    }
    case 'sphere':
      object = new THREE.Mesh(new THREE.SphereBufferGeometry(size[0], 24, 16), material);
      break;
    case 'ellipsoid': {
      const g = new THREE.SphereBufferGeometry(1, 24, 16);
      g.scale(size[0], size[1], size[2]);
      object = new THREE.Mesh(g, material);
      break;
    }
    case 'capsule': {
      // r111 has no CapsuleGeometry: a cylinder and a sphere at each end.
      object = new THREE.Group();
      const body = new THREE.CylinderBufferGeometry(size[0], size[0], 2 * size[1], 24, 1, true);
      body.rotateX(Math.PI / 2);
      object.add(new THREE.Mesh(body, material));
      for (const end of [-1, 1]) {
        const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(size[0], 24, 12), material);
        cap.position.z = end * size[1];
        object.add(cap);
      }
      break;
    }
    case 'cylinder': {
      const g = new THREE.CylinderBufferGeometry(size[0], size[0], 2 * size[1], 24);
      g.rotateX(Math.PI / 2);
      object = new THREE.Mesh(g, material);
      break;
    }
    default: // box, and mesh as its bounding box
      object = new THREE.Mesh(new THREE.BoxBufferGeometry(2 * size[0], 2 * size[1], 2 * (size[2] ?? size[0])), material);
  }
  object.visible = (rgba[3] ?? 1) > 0;
  object.matrixAutoUpdate = false;
  object.name = geom.name ?? '';
  return object;
}

function placeGeom(object, geom) {
  const p = geom.pos ?? [0, 0, 0];
  const m = geom.mat ?? [1, 0, 0, 0, 1, 0, 0, 0, 1];
  // mat is row-major, as Matrix4.set takes its arguments.
  object.matrix.set(m[0], m[1], m[2], p[0], m[3], m[4], m[5], p[1], m[6], m[7], m[8], p[2], 0, 0, 0, 1);
  object.matrixWorldNeedsUpdate = true;
}

function buildScene(result) {
  const canvas = $('physics-canvas');
  if (!view3d) {
    if (typeof THREE === 'undefined') throw new Error('three.js did not load');
    const renderer = new THREE.WebGLRenderer({canvas, antialias: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xeef1f5);
    const camera = new THREE.PerspectiveCamera(40, 1, 0.005, 100);
    camera.up.set(0, 0, 1);  // MuJoCo is z-up
    const controls = new THREE.OrbitControls(camera, canvas);
    controls.enableDamping = false;
    controls.addEventListener('change', draw);
    view3d = {renderer, camera, controls, scene: null, geoms: [], signature: ''};
  }
  const scene = new THREE.Scene();
  // A soft sky and a key light from the camera's side, a weaker one from behind: enough shading
  // that a white arm is not a flat silhouette.
  const sky = new THREE.HemisphereLight(0xffffff, 0x556677, 0.55);
  sky.position.set(0, 0, 1);
  scene.add(sky);
  const sun = new THREE.DirectionalLight(0xffffff, 0.75);
  sun.position.set(1, -2, 2.5);
  scene.add(sun);
  const fill = new THREE.DirectionalLight(0xffffff, 0.25);
  fill.position.set(-1.5, 1, 0.5);
  scene.add(fill);
  // How big the world is, from the geoms that are not planes: for the planes and the camera.
  const box = new THREE.Box3();
  for (const geom of result.geoms) {
    if (geom.type === 'plane') continue;
    const r = Math.max(...(geom.size ?? [0.01]).map(Math.abs), 0.005);
    const p = new THREE.Vector3(...(geom.pos ?? [0, 0, 0]));
    box.expandByPoint(p.clone().addScalar(r));
    box.expandByPoint(p.clone().addScalar(-r));
  }
  if (box.isEmpty()) box.set(new THREE.Vector3(-0.1, -0.1, 0), new THREE.Vector3(0.1, 0.1, 0.2));
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const radius = Math.max(sphere.radius, 0.05);
  // The world frame at its origin, and without a ground plane in the MJCF a grid on z = 0 for
  // scale (its squares a round size: 1, 2 or 5 × a power of ten metres).
  scene.add(new THREE.AxesHelper(Math.min(0.05, radius / 3)));
  if (!result.geoms.some((geom) => geom.type === 'plane')) {
    const raw = radius / 4;
    const power = 10 ** Math.floor(Math.log10(raw));
    const cell = [1, 2, 5, 10].map((f) => f * power).find((f) => f >= raw);
    const cells = 2 * Math.ceil((radius * 2) / cell);
    const grid = new THREE.GridHelper(cells * cell, cells, 0x9aa5b1, 0xc9d1da);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(Math.round(sphere.center.x / cell) * cell, Math.round(sphere.center.y / cell) * cell, 0);
    scene.add(grid);
    view3d.gridCell = cell;
  } else {
    view3d.gridCell = null;
  }
  const geoms = result.geoms.map((geom) => {
    const object = makeGeom(geom, radius * 3);
    placeGeom(object, geom);
    scene.add(object);
    return object;
  });
  view3d.scene = scene;
  view3d.geoms = geoms;
  view3d.signature = signatureOf(result);
  const distance = radius / Math.sin((view3d.camera.fov * Math.PI) / 360) * 1.05;
  const c = sphere.center;
  view3d.camera.position.set(c.x + distance * 0.6, c.y - distance * 0.75, c.z + distance * 0.35);
  view3d.controls.target.copy(c);
  view3d.controls.update();
  const notes = [...(result.notes ?? [])];
  if (view3d.gridCell) notes.push(`grid squares ${num(view3d.gridCell * 100)} cm on z = 0`);
  notes.push('drag to turn, wheel to zoom, right-drag to pan');
  setText($('physics-notes'), notes.join('; '));
}

function signatureOf(result) {
  return result.geoms.map((g) => `${g.name}:${g.type}:${(g.size ?? []).join(',')}`).join('|');
}

function resize() {
  const canvas = $('physics-canvas');
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  if (!width || !height) return;
  const size = view3d.renderer.getSize(new THREE.Vector2());
  if (size.x !== width || size.y !== height) {
    view3d.renderer.setSize(width, height, false);
    view3d.camera.aspect = width / height;
    view3d.camera.updateProjectionMatrix();
  }
}

function draw() {
  if (!view3d?.scene || !visible) return;
  resize();
  view3d.renderer.render(view3d.scene, view3d.camera);
}

function updateScene(result) {
  if (!view3d || view3d.signature !== signatureOf(result)) {
    buildScene(result);
  } else {
    result.geoms.forEach((geom, i) => placeGeom(view3d.geoms[i], geom));
  }
  draw();
  const bodies = [...new Set(result.geoms.map((g) => g.body).filter((b) => b && b !== 'world'))];
  fillSelect($('push-body'), [['', '(none)'], ...bodies.map((b) => [b, b])]);
}

function degreesOfServo(servo) {
  // The shaft's angle from the middle of its range, for a slider without a hand: a guess from
  // Present Position on the common resolutions (4096 pulses a turn, or 1024 over 300°).
  const s = servos.servos().find((x) => x.port === servo.port && x.id === servo.servo);
  if (!s || typeof s.present_position !== 'number') return 0;
  const info = servos.infoNow(s.port, s.id, s.model);
  const goal = info?.table?.items?.find((i) => i.key === 'goal_position');
  if (goal && goal.max === 1023) return (s.present_position - 512) * 300 / 1024;
  return ((s.present_position % 4096) - 2048) * 360 / 4096;
}

function renderJoints(result) {
  const joints = result.joints ?? [];
  const body = $('physics-joints').tBodies[0];
  const signature = joints.map((j) => `${j.joint}:${j.port ?? ''}:${j.servo ?? ''}`).join('|');
  if (signature !== jointsSignature) {
    jointsSignature = signature;
    body.replaceChildren(...joints.map((j) => el('tr', {dataset: {joint: j.joint}},
      el('td', {}, j.joint),
      el('td', {}, j.servo !== undefined && j.servo !== null ? `${j.port}/${j.servo}` : ''),
      el('td', {class: 'num pos'}),
      el('td', {class: 'num vel'}),
      el('td', {class: 'num torque'}),
      el('td', {class: 'slider'}))));
    for (const row of body.rows) {
      const j = joints.find((x) => x.joint === row.dataset.joint);
      const cell = row.querySelector('td.slider');
      cell.replaceChildren();
      if (j?.servo === undefined || j?.servo === null) continue;
      const slider = el('input', {type: 'range', min: '-180', max: '180', step: '1', value: String(Math.round(degreesOfServo(j))),
                                  dataset: {joint: j.joint, port: j.port, servo: String(j.servo)},
                                  title: `hand.move: servo ${j.servo} of ${j.port}, degrees from the middle of its range`});
      cell.append(slider, el('span', {class: 'num hand-value'}));
    }
    fillSelect($('push-joint'), [['', '(none)'], ...joints.map((j) => [j.joint, j.joint])]);
  }
  const isSlide = (j) => j.type === 'slide';
  for (const row of body.rows) {
    const j = joints.find((x) => x.joint === row.dataset.joint);
    if (!j) continue;
    setText(row.querySelector('td.pos'), isSlide(j) ? `${fmt(j.position_rad, 4)} m` : fmt(j.position_rad * kRadToDeg, 1));
    setText(row.querySelector('td.vel'), fmt(j.velocity_rad_s * kRadToDeg, 1));
    setText(row.querySelector('td.torque'), fmt(j.servo_torque_nm, 3));
    const slider = row.querySelector('input[type=range]');
    if (!slider) continue;
    const hand = hands.get(`${j.port}/${j.servo}`);
    setText(row.querySelector('.hand-value'), hand === undefined ? '' : fmt(hand, 1));
    const state = sliders.get(j.joint);
    const idle = !state || (!state.busy && performance.now() > state.holdUntil);
    if (idle && hand !== undefined && document.activeElement !== slider) slider.value = String(Math.round(hand));
  }
}

/** Sends hand.move for a slider: one request at a time per joint, the latest value last. */
async function moveJoint(slider) {
  const joint = slider.dataset.joint;
  let state = sliders.get(joint);
  if (!state) {
    state = {busy: false, queued: false, holdUntil: 0};
    sliders.set(joint, state);
  }
  state.holdUntil = performance.now() + 1000;
  if (state.busy) {
    state.queued = true;
    return;
  }
  state.busy = true;
  do {
    state.queued = false;
    const position = Number(slider.value);
    const reply = await api.request({cmd: 'hand.move', port: slider.dataset.port, joint: Number(slider.dataset.servo),
                                     position, duration_s: 0.2}).catch(() => null);
    if (reply && !reply.ok) {
      showMessage($('physics-message'), reply.error, false);
      // "gripper 120° is outside its range -10 ~ 100°": the slider learns the range.
      const range = /outside its range (-?[\d.]+) ~ (-?[\d.]+)°/.exec(reply.error);
      if (range) {
        slider.min = range[1];
        slider.max = range[2];
      }
    } else if (reply) {
      showMessage($('physics-message'), `${joint}: hand.move to ${position}°`, true);
    }
  } while (state.queued);
  state.busy = false;
  state.holdUntil = performance.now() + 500;
}

function parseVector(text) {
  const parts = text.split(/[\s,]+/).filter(Boolean).map(Number);
  return parts.length === 3 && parts.every(Number.isFinite) ? parts : null;
}

async function push(clear) {
  const joint = $('push-joint').value;
  const bodyName = $('push-body').value;
  const requests = [];
  if (joint) {
    const torque = clear ? 0 : Number($('push-torque').value);
    if (clear || $('push-torque').value.trim() !== '') requests.push({cmd: 'physics.apply', joint, torque_nm: torque});
  }
  if (bodyName) {
    if (clear) requests.push({cmd: 'physics.apply', body: bodyName, force_n: [0, 0, 0], torque_nm: [0, 0, 0]});
    else if ($('push-force').value.trim() !== '') {
      const force = parseVector($('push-force').value);
      if (!force) {
        showMessage($('push-message'), 'the force is three numbers: x, y, z (N, world frame)', false);
        return;
      }
      requests.push({cmd: 'physics.apply', body: bodyName, force_n: force});
    }
  }
  if (!requests.length) {
    showMessage($('push-message'), 'choose a joint and a torque, or a body and a force', false);
    return;
  }
  const said = [];
  for (const req of requests) {
    const reply = await api.request(req);
    if (!reply.ok) {
      showMessage($('push-message'), reply.error, false);
      return;
    }
    said.push(req.joint ? `${req.joint}: ${req.torque_nm} N·m` : `${req.body}: [${req.force_n.join(', ')}] N`);
  }
  showMessage($('push-message'), `${clear ? 'cleared' : 'applied'}: ${said.join('; ')}`, true);
}

async function poll() {
  if (!available) return;
  const askHands = polls++ % 5 === 0;
  const [scene, state, held] = await Promise.all([
    api.request({cmd: 'physics.scene'}, {quiet: true}),
    api.call('physics'),
    askHands ? api.request({cmd: 'hand'}, {quiet: true}) : null,
  ]);
  if (askHands && held?.ok) {
    hands = new Map((held.result ?? []).filter((h) => h.units === undefined || h.units === 'deg')
      .map((h) => [`${h.port}/${h.servo}`, h.value]));
  }
  if (polls % 20 === 1) servos.refresh().catch(() => {});
  renderJoints(state);
  if (scene.ok) {
    try {
      updateScene(scene.result);
    } catch (error) {
      setText($('physics-notes'), `cannot draw the world: ${error.message}`);
    }
  } else if (!view3d) {
    setText($('physics-notes'), `no scene: ${scene.error}`);
  }
}

async function connected() {
  const reply = await api.request({cmd: 'physics'}, {quiet: true});
  available = reply.ok;
  context.setPhysicsTab(available);
  if (available) {
    renderJoints(reply.result);
    if (exported.showWhenReady) context.showView('physics');
  }
  exported.showWhenReady = false;
}

function init(ctx) {
  context = ctx;
  $('physics-joints').addEventListener('input', (event) => {
    const slider = event.target.closest('input[type=range][data-joint]');
    if (slider) moveJoint(slider);
  });
  $('push-apply').addEventListener('click', () => push(false).catch(() => {}));
  $('push-clear').addEventListener('click', () => push(true).catch(() => {}));
  window.addEventListener('resize', draw);
}

const exported = {
  name: 'physics',
  periodMs: 50,
  showWhenReady: false,
  init,
  poll,
  connected,
  show() {
    visible = true;
    draw();
  },
  hide() {
    visible = false;
  },
};
export default exported;
