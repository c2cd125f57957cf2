// Loads a GLB with three.js's GLTFLoader (Debian libjs-three) in Node and prints the names of
// its meshes and point sets as JSON: an independent glTF reader for inspect_cli_test.
// Usage: node gltf_probe.js FILE.glb THREE_DIR  (THREE_DIR: /usr/share/javascript/three)
const fs = require('fs');
const vm = require('vm');
const dir = process.argv[3];
global.THREE = require(dir + '/three.js');
// The examples/js loader is a UMD script: run it where only the global THREE is in scope.
vm.runInThisContext(fs.readFileSync(dir + '/examples/js/loaders/GLTFLoader.js', 'utf8'));
const buf = fs.readFileSync(process.argv[2]);
const ab = buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength);
new THREE.GLTFLoader().parse(ab, '', (gltf) => {
  const names = [];
  gltf.scene.traverse((o) => {
    if (o.isMesh || o.isPoints) names.push(o.name);
  });
  console.log(JSON.stringify({names}));
}, (e) => {
  console.error('GLTFLoader: ' + e);
  process.exit(1);
});
