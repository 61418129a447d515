// The comparison scenes run in the WebAssembly module under node (tests/web/compare_native_wasm.py):
//   node tests/web/web_scenes.cjs build/web/astrojax.js SCENE
// prints sceneReport(SCENE), the same text the native web_scenes prints.
'use strict';
const path = require('path');
const [modulePath, scene] = process.argv.slice(2);
if (!modulePath || !scene) {
  process.stderr.write('usage: node web_scenes.cjs ASTROJAX_JS SCENE\n');
  process.exit(2);
}
require(path.resolve(modulePath))().then((M) => {
  process.stdout.write(M.sceneReport(scene));
});
