// taskmap viewer, shared part: errors on the page, the data block, the 3-D view (z up), hand
// meshes and kinematics (the same as HandModel::linkPoses), colours.
'use strict';
const TM = {};
TM.fail = function (message) {
  console.error('taskmap viewer: ' + message);
  const box = document.getElementById('tm-error');
  box.textContent += message + '\n';
  box.style.display = 'block';
  document.body.setAttribute('data-error', '1');
};
window.addEventListener('error', (ev) => TM.fail(ev.message + ' (' + (ev.lineno || '?') + ')'));
window.addEventListener('unhandledrejection', (ev) => TM.fail(String(ev.reason)));
TM.data = JSON.parse(document.getElementById('tm-data').textContent);
TM.hash = {};
location.hash.replace(/^#/, '').split('&').forEach((kv) => {
  const [k, v] = kv.split('=');
  if (k) TM.hash[k] = v === undefined ? '1' : decodeURIComponent(v);
});
TM.palette = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',
  '#bcbd22', '#17becf', '#393b79', '#637939', '#8c6d31', '#843c39', '#7b4173'];
TM.outlierColor = '#9a9a9a';
TM.clusterColor = (c) => (c === null || c === undefined ? TM.palette[0]
  : c < 0 ? TM.outlierColor : TM.palette[c % TM.palette.length]);
TM.el = function (tag, attrs, text) {
  const e = document.createElement(tag);
  for (const k in attrs || {}) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  return e;
};
TM.fmt = (x, d) => (typeof x === 'number' ? x.toFixed(d === undefined ? 4 : d) : String(x));
// Pose x y z qw qx qy qz at a[7 i] as a Matrix4.
TM.poseMatrix = function (a, i) {
  const o = 7 * (i || 0);
  const q = new THREE.Quaternion(a[o + 4], a[o + 5], a[o + 6], a[o + 3]).normalize();
  return new THREE.Matrix4().compose(new THREE.Vector3(a[o], a[o + 1], a[o + 2]), q,
    new THREE.Vector3(1, 1, 1));
};
// The page layout: side panel and the view with a details box.
TM.layout = function () {
  const app = document.getElementById('tm-app');
  const side = TM.el('div', { id: 'tm-side' });
  const view = TM.el('div', { id: 'tm-view' });
  const details = TM.el('div', { id: 'tm-details' });
  view.appendChild(details);
  app.appendChild(side);
  app.appendChild(view);
  return { side, view, details };
};
// Renderer, z-up camera, orbit/pan/zoom controls, lights; render() draws once.
TM.viewer = function (container) {
  const renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xf4f4f2, 1);  // alpha: some software compositors show an opaque canvas black
  container.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 100);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 0.75));
  const sun = new THREE.DirectionalLight(0xffffff, 0.55);
  camera.add(sun);
  sun.position.set(0.5, 1, 0.8);
  scene.add(camera);
  const v = { renderer, scene, camera, controls: null };
  v.render = () => renderer.render(scene, camera);
  v.resize = () => {
    const w = container.clientWidth || 800, h = container.clientHeight || 600;
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    v.render();
  };
  window.addEventListener('resize', v.resize);
  v.controls = new THREE.OrbitControls(camera, renderer.domElement);
  v.controls.screenSpacePanning = true;
  v.controls.addEventListener('change', v.render);
  // Fixed views: front looks along +y (x to the right, z up), top along -z, side along -x.
  v.look = (center, radius, name) => {
    const dirs = { front: [0, -1, 0], top: [0, -0.001, 1], side: [1, 0, 0], iso: [0.55, -0.75, 0.45] };
    const d = new THREE.Vector3().fromArray(dirs[name] || dirs.iso).normalize();
    const dist = radius / Math.sin(camera.fov * Math.PI / 360);
    camera.position.copy(center).addScaledVector(d, dist);
    camera.near = dist / 100;
    camera.far = dist * 10;
    camera.updateProjectionMatrix();
    v.controls.target.copy(center);
    v.controls.update();
    v.render();
  };
  v.resize();
  return v;
};
// Object mesh from flat vertices v and faces f.
TM.meshGeometry = function (v, f) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(v, 3));
  g.setIndex(f);
  g.computeVertexNormals();
  return g;
};
TM.objectMesh = function (o) {
  const m = new THREE.MeshLambertMaterial({ color: 0xd8cfc4, side: THREE.DoubleSide });
  return new THREE.Mesh(TM.meshGeometry(o.v, o.f), m);
};
// One collision shape as a geometry in its link frame.
TM.shapeGeometry = function (s) {
  let g;
  if (s.t === 'box') g = new THREE.BoxBufferGeometry(s.s[0], s.s[1], s.s[2]);
  else if (s.t === 'sph') g = new THREE.SphereBufferGeometry(s.r, 16, 12);
  else if (s.t === 'cyl') g = new THREE.CylinderBufferGeometry(s.r, s.r, s.l, 20).rotateX(Math.PI / 2);
  else {
    const pts = [];
    for (let i = 0; i + 2 < s.p.length; i += 3) pts.push(new THREE.Vector3(s.p[i], s.p[i + 1], s.p[i + 2]));
    try {
      g = new THREE.ConvexBufferGeometry(pts);
    } catch (e) {
      g = new THREE.SphereBufferGeometry(0.002, 6, 4);
    }
  }
  g.applyMatrix(TM.poseMatrix(s.o));
  return g;
};
// Prepares a hand: shape geometries per link, joint origins, palm-from-root.
TM.prepareHand = function (h) {
  h.geoms = h.links.map((l) => l.shapes.map(TM.shapeGeometry));
  h.jointOrigins = h.joints.map((j) => TM.poseMatrix(j.o));
  h.palmFromRoot = new THREE.Matrix4().getInverse(TM.poseMatrix(h.root_to_palm));
  return h;
};
// Link poses in the palm frame for actuated values q (clamped to the limits): linkPoses.
TM.linkPoses = function (h, q) {
  const poses = h.links.map(() => new THREE.Matrix4());
  h.joints.forEach((j, k) => {
    const t = poses[j.parent].clone().multiply(h.jointOrigins[k]);
    if (j.d >= 0) {
      const qd = Math.min(Math.max(q[j.d], h.lower[j.d]), h.upper[j.d]);
      const v = j.m * qd + j.off;
      const axis = new THREE.Vector3().fromArray(j.axis);
      if (j.t === 'r') t.multiply(new THREE.Matrix4().makeRotationAxis(axis.normalize(), v));
      else if (j.t === 'p') t.multiply(new THREE.Matrix4().makeTranslation(axis.x * v, axis.y * v, axis.z * v));
    }
    poses[j.child] = t;
  });
  return poses.map((p) => h.palmFromRoot.clone().multiply(p));
};
// A hand posed by q as a Group in the palm frame; link groups carry userData.link.
TM.handGroup = function (h, q, material) {
  const group = new THREE.Group();
  const poses = TM.linkPoses(h, q);
  h.links.forEach((l, i) => {
    if (h.geoms[i].length === 0) return;
    const lg = new THREE.Group();
    lg.matrixAutoUpdate = false;
    lg.matrix.copy(poses[i]);
    lg.userData.link = i;
    h.geoms[i].forEach((g) => lg.add(new THREE.Mesh(g, material)));
    group.add(lg);
  });
  return group;
};
TM.handMaterial = (color, ghost) => new THREE.MeshLambertMaterial({
  color, transparent: !!ghost, opacity: ghost ? 0.18 : 1, depthWrite: !ghost });
// Bounding sphere of flat vertices.
TM.bounds = function (v) {
  const box = new THREE.Box3();
  for (let i = 0; i + 2 < v.length; i += 3) box.expandByPoint(new THREE.Vector3(v[i], v[i + 1], v[i + 2]));
  const center = box.isEmpty() ? new THREE.Vector3() : box.getCenter(new THREE.Vector3());
  const radius = box.isEmpty() ? 0.1 : Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  return { center, radius };
};
// Marks the page drawn: <body data-ready="n"> once a frame is rendered (drawing is synchronous),
// and data-draw-ms: milliseconds from navigation start to then.
TM.ready = function (v, n) {
  v.render();
  document.body.setAttribute('data-draw-ms', String(Math.round(performance.now())));
  document.body.setAttribute('data-ready', String(n));
  requestAnimationFrame(v.render);
};
TM.run = function (main) {
  try {
    main();
  } catch (e) {
    TM.fail(e && e.stack ? e.stack : String(e));
  }
};
