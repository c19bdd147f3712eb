// Copies the configurator's built web UI (tvl_lsp/ui/static, built from editors/configurator and
// committed) into the extension, for the "TVL: Open configurator" webview.
const fs = require('fs');
const path = require('path');

const src = path.join(__dirname, '..', '..', '..', 'tvl_lsp', 'ui', 'static');
const dst = path.join(__dirname, '..', 'out', 'configurator');
fs.mkdirSync(dst, { recursive: true });
for (const name of ['app.js', 'app.css', 'elk-worker.js', 'THIRD-PARTY-NOTICES.txt']) {
  fs.copyFileSync(path.join(src, name), path.join(dst, name));
}
console.log(`configurator UI copied to ${path.relative(process.cwd(), dst)}`);
