// taskmap hand-info --html: the hand in its palm frame, posed by one slider per actuated joint;
// the open preshape as a ghost, buttons for open and closed, palm frame axes, approach arrow.
TM.run(function () {
  const h = TM.prepareHand(TM.data.hand);
  const ui = TM.layout();
  const v = TM.viewer(ui.view);
  const q = h.preshape.slice();
  const solid = TM.handMaterial(0x1f77b4, false);
  let posed = null;
  const pose = () => {
    if (posed) v.scene.remove(posed);
    posed = TM.handGroup(h, q, solid);
    v.scene.add(posed);
    v.render();
  };
  v.scene.add(TM.handGroup(h, h.preshape, TM.handMaterial(0x888888, true)));
  const reach = Math.max(h.reach, 0.02);
  v.scene.add(new THREE.AxesHelper(0.5 * reach));
  const a = new THREE.Vector3().fromArray(h.approach).normalize();
  v.scene.add(new THREE.ArrowHelper(a, a.clone().multiplyScalar(-1.4 * reach), 1.0 * reach, 0xd01010, 0.15 * reach, 0.08 * reach));
  ui.side.appendChild(TM.el('h1', {}, 'hand ' + h.name));
  ui.side.appendChild(TM.el('div', { class: 'tm-note' }, TM.data.source));
  ui.side.appendChild(TM.el('div', { class: 'tm-note' }, 'palm frame: x red, y green, z blue; red arrow: the approach axis (the direction the hand ' +
    'moves toward the object); grey ghost: open preshape; blue: the sliders\' pose'));
  const sliders = [];
  const setAll = (values) => { values.forEach((x, k) => { q[k] = x; sliders[k].value = String(x); }); pose(); };
  const buttons = TM.el('div');
  [['open (preshape)', h.preshape], ['closed', h.closed]].forEach(([label, values]) => {
    const b = TM.el('button', {}, label);
    b.onclick = () => setAll(values);
    buttons.appendChild(b);
  });
  ui.side.appendChild(buttons);
  const blend = TM.el('input', { type: 'range', min: '0', max: '1', step: '0.01', value: '0', id: 'tm-close' });
  blend.oninput = () => setAll(h.preshape.map((p, k) => p + (h.closed[k] - p) * Number(blend.value)));
  const bl = TM.el('label', {}, 'open \u2192 closed');
  bl.appendChild(blend);
  ui.side.appendChild(bl);
  ui.side.appendChild(TM.el('h2', {}, 'joints'));
  h.joint_names.forEach((name, k) => {
    const s = TM.el('input', { type: 'range', min: String(h.lower[k]), max: String(h.upper[k]), step: String((h.upper[k] - h.lower[k]) / 200 || 0.001), value: String(q[k]) });
    const l = TM.el('label', {}, name + ' [' + TM.fmt(h.lower[k], 3) + ', ' + TM.fmt(h.upper[k], 3) + ']');
    s.oninput = () => { q[k] = Number(s.value); pose(); };
    l.appendChild(s);
    sliders.push(s);
    ui.side.appendChild(l);
  });
  if (TM.hash.pose === 'closed') {
    blend.value = '1';
    setAll(h.closed);
  }
  else pose();
  v.look(new THREE.Vector3(), 1.3 * reach, TM.hash.view || 'iso');
  TM.ready(v, 1);
});
