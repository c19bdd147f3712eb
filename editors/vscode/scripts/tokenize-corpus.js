// Tokenizes every TVL model (.tvl) and ROS launch file (.launch, .launch.xml, .test) under the
// given folders with the extension's grammars, as VS Code would, and fails when
//  - a .tvl line gets an invalid.* scope, or tokenizing throws or takes over 1 s a file;
//  - a .tvl file whose braces balance (outside comments and strings) does not end at the top
//    level of the grammar (a begin/end rule leaked past its closing brace);
//  - a $(arg|find|env|optenv|anon ...) in a launch file's attribute value or text is not
//    highlighted as a substitution (the injection grammar did not apply).
// Usage: node scripts/tokenize-corpus.js DIR... (default: the repository's examples/ and tests/data/;
// scripts/ci_editors.sh also passes ../shared/corpus where it exists)
'use strict';
const fs = require('fs');
const path = require('path');
const tm = require('vscode-textmate');
const onig = require('vscode-oniguruma');

const ext = path.resolve(__dirname, '..');
const grammarFiles = {
  'source.tvl': path.join(ext, 'syntaxes', 'tvl.tmLanguage.json'),
  'text.xml.roslaunch': path.join(ext, 'syntaxes', 'roslaunch.tmLanguage.json'),
  'source.launch-substitution.injection': path.join(ext, 'syntaxes', 'launch-substitution.injection.tmLanguage.json'),
  'text.xml': path.join(ext, 'node_modules', 'tm-grammars', 'grammars', 'xml.json'),
};

function walk(dir, out) {
  for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
    const p = path.join(dir, e.name);
    if (e.isDirectory()) walk(p, out);
    else if (/\.(tvl|launch|test)$|\.launch\.xml$/.test(e.name)) out.push(p);
  }
  return out;
}

// brace balance of TVL source outside comments and strings
function bracesBalanced(text) {
  let depth = 0;
  const s = text.replace(/\/\*[\s\S]*?\*\//g, '').replace(/\/\/.*$/gm, '').replace(/"(?:\\.|[^"\\\n])*"/g, '""');
  for (const ch of s) {
    if (ch === '{') depth++;
    else if (ch === '}') {
      depth--;
      if (depth < 0) return false;
    }
  }
  return depth === 0;
}

async function main() {
  const dirs = process.argv.slice(2);
  if (dirs.length === 0) dirs.push(path.resolve(ext, '..', '..', 'examples'), path.resolve(ext, '..', '..', 'tests', 'data'));
  const wasm = fs.readFileSync(path.join(path.dirname(require.resolve('vscode-oniguruma')), 'onig.wasm')).buffer;
  await onig.loadWASM(wasm);
  const registry = new tm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (p) => new onig.OnigScanner(p),
      createOnigString: (s) => new onig.OnigString(s),
    }),
    loadGrammar: async (scope) => {
      const f = grammarFiles[scope];
      return f ? tm.parseRawGrammar(fs.readFileSync(f, 'utf8'), f) : null;
    },
    getInjections: (scope) => (scope === 'text.xml.roslaunch' ? ['source.launch-substitution.injection'] : []),
  });
  const tvl = await registry.loadGrammar('source.tvl');
  const launch = await registry.loadGrammar('text.xml.roslaunch');
  const files = dirs.flatMap((d) => walk(d, []));
  const problems = [];
  const counts = { tvl: 0, launch: 0, lines: 0, tokens: 0, unbalanced: 0, substitutions: 0, checked: 0 };
  for (const f of files) {
    const isTvl = f.endsWith('.tvl');
    const text = fs.readFileSync(f, 'utf8');
    const grammar = isTvl ? tvl : launch;
    let stack = tm.INITIAL;
    // CPU time, not wall time: a runaway regex shows in both, a loaded machine only in the wall clock
    const t0 = process.cpuUsage();
    const lines = text.split(/\r\n|\r|\n/);
    try {
      lines.forEach((line, i) => {
        const r = grammar.tokenizeLine(line, stack, 1000);
        if (r.stoppedEarly) problems.push(`${f}:${i + 1}: tokenizing stopped early (time limit)`);
        stack = r.ruleStack;
        counts.tokens += r.tokens.length;
        for (const t of r.tokens) {
          const scopes = t.scopes.join(' ');
          if (scopes.includes('meta.substitution.') && t.scopes.some((s) => s.startsWith('punctuation.definition.substitution.begin'))) counts.substitutions++;
          if (isTvl && /(^| )invalid\./.test(scopes)) {
            problems.push(`${f}:${i + 1}:${t.startIndex + 1}: ${JSON.stringify(line.slice(t.startIndex, t.endIndex))} is ${scopes}`);
          }
        }
      });
    } catch (err) {
      problems.push(`${f}: tokenizing threw ${err}`);
    }
    const used = process.cpuUsage(t0);
    const ms = Math.round((used.user + used.system) / 1000);
    if (ms > 1000) problems.push(`${f}: took ${ms} ms of CPU time`);
    counts.lines += lines.length;
    if (isTvl) {
      counts.tvl++;
      if (bracesBalanced(text)) {
        if (stack.depth !== 1) problems.push(`${f}: braces balance but the grammar ends ${stack.depth - 1} rule(s) deep`);
      } else {
        counts.unbalanced++;
      }
    } else {
      counts.launch++;
    }
    if (!isTvl) {
      // every $(arg X) outside a comment is highlighted as a substitution (the injection works)
      let st = tm.INITIAL;
      lines.forEach((line, i) => {
        const r = grammar.tokenizeLine(line, st, 1000);
        st = r.ruleStack;
        for (const m of line.matchAll(/\$\((arg|find|env|optenv|anon)\s+[^\s()$]+\s*\)/g)) {
          const tok = r.tokens.find((t) => t.startIndex <= m.index && m.index < t.endIndex);
          const scopes = tok ? tok.scopes.join(' ') : '';
          if (/comment|cdata/.test(scopes) || !/meta\.tag|string/.test(scopes) && !/meta\.substitution/.test(scopes)) continue;
          if (!scopes.includes(`meta.substitution.${m[1] === 'optenv' ? 'env' : m[1]}.roslaunch`)) {
            problems.push(`${f}:${i + 1}:${m.index + 1}: ${m[0]} is not highlighted (${scopes})`);
          } else {
            counts.checked++;
          }
        }
      });
    }
  }
  console.log(`tokenized ${counts.tvl} .tvl files and ${counts.launch} launch files (${counts.lines} lines, ${counts.tokens} tokens, ${counts.substitutions} substitutions, ${counts.checked} checked); ${counts.unbalanced} .tvl files have unbalanced braces`);
  if (problems.length) {
    console.error(problems.join('\n'));
    console.error(`${problems.length} problem(s)`);
    process.exit(1);
  }
  if (counts.tvl === 0) {
    console.error('no .tvl file found');
    process.exit(1);
  }
}

main().catch((e) => {
  console.error(e);
  process.exit(2);
});
