// Copies the TextMate grammars kept at the repository's top level (grammars/) into the
// extension (syntaxes/), so that the .vsix carries them. Run by `npm run build`.
'use strict';
const fs = require('fs');
const path = require('path');

const src = path.resolve(__dirname, '..', '..', '..', 'grammars');
const dst = path.resolve(__dirname, '..', 'syntaxes');
const files = [
  'tvl.tmLanguage.json',
  'roslaunch.tmLanguage.json',
  'launch-substitution.injection.tmLanguage.json',
];
fs.mkdirSync(dst, { recursive: true });
for (const f of files) {
  const from = path.join(src, f);
  const text = fs.readFileSync(from, 'utf8');
  JSON.parse(text); // fail loudly on a broken grammar
  fs.writeFileSync(path.join(dst, f), text);
}
console.log(`copied ${files.length} grammars from ${src}`);
