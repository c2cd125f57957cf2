// taskmap view reach.h5: robot and scene primitives along the planned path with a time slider
// and play button, the map's hand (its collision shapes, closing to the chosen grasp at the end;
// without it the planner's primitives of the hand), the object mesh, the chosen grasp's palm
// frame, and the cost terms.
// A sphere-swept primitive (capsule or rectangle) as in the GLB export: a UV sphere of the sweep
// radius whose vertices move by +-half_u along u and +-half_v along v.
TM.primitiveGeometry = function (s) {
  // Pole along z, longitudes half a step off the axes: no vertex on u = 0 or v = 0 but the poles.
  const g = new THREE.SphereBufferGeometry(Math.max(s.r, 1e-4), 16, 9, Math.PI / 16).rotateX(Math.PI / 2);
  const p = g.attributes.position;
  const ax = s.axes;  // row by row: column k is (ax[k], ax[3 + k], ax[6 + k])
  for (let i = 0; i < p.count; ++i) {
    const x = p.getX(i), y = p.getY(i), z = p.getZ(i);
    const lx = x + Math.sign(x) * s.hu, ly = y + Math.sign(y) * s.hv;
    p.setXYZ(i, s.c[0] + ax[0] * lx + ax[1] * ly + ax[2] * z, s.c[1] + ax[3] * lx + ax[4] * ly + ax[5] * z,
      s.c[2] + ax[6] * lx + ax[7] * ly + ax[8] * z);
  }
  g.computeVertexNormals();
  return g;
};
// A cost value in at most 9 characters: 4 significant digits, with an exponent from 10^5 up and
// below 10^-3 (the table must fit the side panel whatever the terms' scale).
TM.fmtCost = function (x) {
  if (typeof x !== 'number' || !isFinite(x)) return String(x);
  const a = Math.abs(x);
  if (a === 0) return '0';
  if (a >= 1e5 || a < 1e-3) return x.toExponential(3).replace('e+', 'e');
  return String(Number(x.toPrecision(4)));
};
// Cost terms table: first and last iteration (full values in the cells' tooltips).
TM.costTable = function (side, plan) {
  const terms = plan.cost_terms, C = terms.length, rows = plan.cost_history.length / Math.max(C, 1);
  side.appendChild(TM.el('h2', {}, 'cost terms (' + (rows - 1) + ' iterations)'));
  const t = TM.el('table', { class: 'tm-costs', id: 'tm-costs' });
  const head = TM.el('tr');
  ['term', 'start', 'final'].forEach((x) => head.appendChild(TM.el('th', {}, x)));
  t.appendChild(head);
  const cell = (x) => TM.el('td', { title: String(x) }, TM.fmtCost(x));
  terms.forEach((name, k) => {
    const r = TM.el('tr');
    r.appendChild(TM.el('th', {}, name.replace(/_/g, '_\u200b')));  // may break after '_'
    r.appendChild(cell(plan.cost_history[k]));
    r.appendChild(cell(plan.cost_history[(rows - 1) * C + k]));
    t.appendChild(r);
  });
  side.appendChild(t);
  // The quality term's scale (docs/REACHING.md "The quality term's scale").
  side.appendChild(TM.el('div', { class: 'tm-note', id: 'tm-quality-scale' }, plan.quality_peak !== 1
    ? 'quality = w_q g_q / q*, q* = ' + TM.fmtCost(plan.quality_peak) + ' (-1: the map\'s best grasp)'
    : 'quality = w_q g_q, unscaled (q* = 1)'));
};
// The map's hand as its own collision shapes on the palm, posed per step from the link poses the
// page carries (hand_motion: palm-frame poses per closing stage, the stage of every step);
// returns { group, meshes, show(t) }.
TM.reachHand = function (D, material) {
  const h = TM.prepareHand(D.map_hand), M = D.hand_motion, L = M.links;
  const stages = M.poses.length / (7 * L);
  const poses = [];
  for (let i = 0; i < stages * L; ++i) poses.push(TM.poseMatrix(M.poses, i));
  const group = new THREE.Group();
  const links = [];
  let meshes = 0;
  h.links.forEach((l, i) => {
    if (h.geoms[i].length === 0) return;
    const lg = new THREE.Group();
    lg.matrixAutoUpdate = false;
    h.geoms[i].forEach((g) => lg.add(new THREE.Mesh(g, material)));
    meshes += h.geoms[i].length;
    group.add(lg);
    links.push([i, lg]);
  });
  const show = (t) => {
    const palm = TM.poseMatrix(D.palm_world, t), k = M.stage[t];
    links.forEach(([i, lg]) => lg.matrix.multiplyMatrices(palm, poses[k * L + i]));
  };
  return { group, meshes, show };
};
// Proximity and quality over the movement (weighted map terms per step) with a cursor at the
// shown step; returns the function that moves the cursor.
TM.movementPlot = function (side, plan) {
  side.appendChild(TM.el('h2', {}, 'map terms over the movement'));
  const c = TM.el('canvas', { width: '280', height: '120', id: 'tm-plot' });
  side.appendChild(c);
  side.appendChild(TM.el('div', { class: 'tm-note' }, 'blue: proximity, green: quality, per step'));
  const series = [[plan.proximity, '#1f77b4'], [plan.quality, '#2ca02c']];
  const all = plan.proximity.concat(plan.quality);
  const lo = all.reduce((a, b) => Math.min(a, b), 0), hi = all.reduce((a, b) => Math.max(a, b), 1e-9);
  const n = Math.max(plan.proximity.length - 1, 1);
  const x = (t) => 4 + (272 * t) / n, y = (val) => 116 - (112 * (val - lo)) / (hi - lo || 1);
  return (t) => {
    const g = c.getContext('2d');
    g.clearRect(0, 0, 280, 120);
    g.strokeStyle = '#ccc';
    g.beginPath(); g.moveTo(4, y(0)); g.lineTo(276, y(0)); g.stroke();
    series.forEach(([values, color]) => {
      g.strokeStyle = color;
      g.beginPath();
      values.forEach((val, k) => (k ? g.lineTo(x(k), y(val)) : g.moveTo(x(k), y(val))));
      g.stroke();
    });
    g.strokeStyle = '#d01010';
    g.beginPath(); g.moveTo(x(t), 0); g.lineTo(x(t), 120); g.stroke();
  };
};
TM.run(function () {
  const D = TM.data, B = D.bodies, S = D.rows, nb = B.names.length;
  const ui = TM.layout();
  const v = TM.viewer(ui.view);
  const colors = [0xe07020, 0x3070d0, 0x9a9a9a];
  const mats = colors.map((c) => new THREE.MeshLambertMaterial({ color: c }));
  // With the map's hand, the planner's primitives of the hand are a faint, optional envelope.
  const hand = D.map_hand && D.hand_motion ? TM.reachHand(D, new THREE.MeshLambertMaterial({ color: colors[1] })) : null;
  if (hand) {
    mats[1] = new THREE.MeshLambertMaterial({ color: colors[1], transparent: true, opacity: 0.2, depthWrite: false });
    v.scene.add(hand.group);
  }
  const bodies = B.names.map((name, b) => {
    const g = new THREE.Group();
    g.matrixAutoUpdate = false;
    v.scene.add(g);
    return g;
  });
  D.shapes.forEach((s) => bodies[s.b].add(new THREE.Mesh(TM.primitiveGeometry(s), mats[B.role[s.b]] || mats[0])));
  const object = TM.objectMesh(D.object);
  object.matrixAutoUpdate = false;
  object.matrix.copy(TM.poseMatrix(D.object.pose));
  v.scene.add(object);
  const grasp = new THREE.AxesHelper(0.08);
  grasp.matrixAutoUpdate = false;
  grasp.matrix.copy(TM.poseMatrix(D.palm_world, S - 1));
  v.scene.add(grasp);
  const envelope = [];
  bodies.forEach((g, b) => { if (B.role[b] === 1) envelope.push(g); });
  const label = TM.el('div', { class: 'tm-note' });
  let cursor = () => {};
  const show = (t) => {
    cursor(t);
    if (hand) hand.show(t);
    for (let b = 0; b < nb; ++b) bodies[b].matrix.copy(TM.poseMatrix(B.poses.slice((t * nb + b) * 7, (t * nb + b) * 7 + 7)));
    label.textContent = 't = ' + TM.fmt(t * D.dt, 3) + ' s (step ' + t + ' of ' + (S - 1) + '), proximity ' +
      TM.fmt(D.plan.proximity[t], 4) + ', quality ' + TM.fmt(D.plan.quality[t], 4);
    v.render();
  };
  ui.side.appendChild(TM.el('h1', {}, D.robot + ' + ' + D.hand + ' \u2192 ' + D.object.name));
  ui.side.appendChild(TM.el('div', { class: 'tm-note' }, 'grasp #' + D.plan.grasp_index + ' of ' + D.plan.map_path +
    ' (cluster ' + D.plan.cluster + ', started from cluster ' + D.plan.start_cluster + '); axes: its palm frame'));
  ui.side.appendChild(TM.el('div', { class: 'tm-note', id: 'tm-hand-note' }, hand
    ? 'hand: the map\'s ' + D.map_hand.name + ' (its collision shapes) in its preshape, closing to grasp #' +
      D.plan.grasp_index + '\'s joint values over the last ' + TM.fmt(D.hand_motion.close_s, 2) + ' s (from step ' +
      D.hand_motion.close_from + ')'
    : 'hand: the planner\'s collision primitives (blue); the map\'s hand is not drawn: ' + (D.hand_note || 'not given')));
  if (hand) {
    const shown = TM.el('input', { type: 'checkbox', id: 'tm-envelope' });
    shown.checked = TM.hash.envelope === '1';
    const apply = () => { envelope.forEach((g) => { g.visible = shown.checked; }); v.render(); };
    shown.onchange = apply;
    const l = TM.el('label');
    l.appendChild(shown);
    l.appendChild(document.createTextNode(' the planner\'s collision primitives of the hand'));
    ui.side.appendChild(l);
    envelope.forEach((g) => { g.visible = shown.checked; });
  }
  const slider = TM.el('input', { type: 'range', id: 'tm-time', min: '0', max: String(S - 1), step: '1', value: String(S - 1) });
  slider.oninput = () => show(Number(slider.value));
  const play = TM.el('button', {}, 'play');
  play.onclick = () => {
    let t = 0;
    const step = () => { slider.value = String(t); show(t); if (++t < S) setTimeout(step, 1000 * D.dt); };
    step();
  };
  ui.side.appendChild(play);
  ui.side.appendChild(slider);
  ui.side.appendChild(label);
  TM.costTable(ui.side, D.plan);
  cursor = TM.movementPlot(ui.side, D.plan);
  const box = new THREE.Box3();
  for (let t of [0, S - 1]) for (let b = 0; b < nb; ++b) box.expandByPoint(new THREE.Vector3().fromArray(B.poses, (t * nb + b) * 7));
  box.expandByObject(object);
  const start = TM.hash.step !== undefined ? Number(TM.hash.step) : S - 1;
  slider.value = String(start);
  show(start);
  v.look(box.getCenter(new THREE.Vector3()), box.getSize(new THREE.Vector3()).length() / 2, TM.hash.view || 'iso');
  document.body.setAttribute('data-hand-meshes', String(hand ? hand.meshes : 0));
  TM.ready(v, 1);
});
