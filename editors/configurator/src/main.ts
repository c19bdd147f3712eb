// The configurator's page: feature diagram (left), computation graph and details (right),
// problems (bottom). A thin client: every answer comes from tvl_lsp/configurator through the
// host (tvl-lsp ui over HTTP, or the VS Code extension and the language server).
import { Diagram } from './diagram';
import { basename, el, formatCount } from './format';
import { GraphView } from './graph';
import { makeTransport, Transport } from './transport';
import type {
  Counts, DecideResult, Excerpt, FeatureNode, GenerateResult, GraphEdge, GraphElement, GraphJson, Location, ModelJson,
  Problem, ProblemsJson, Refusal, State, Status, Targets,
} from './types';

const t: Transport = makeTransport();

interface App {
  model: ModelJson;
  state: State;
  counts: Counts | null;
  diagram: Diagram;
  graph: GraphView | null; // null: being built
  graphJson: GraphJson | null;
  graphStatus: Record<string, Status>;
  showRuledOut: boolean;
  showAllProblems: boolean;
  problems: Problem[] | null; // null: being checked
  problemStatus: Record<string, Status>;
}

let app: App | null = null;
let problemsKey = '';
const PROBLEMS_SHOWN = 200;
let countSeq = 0;
let busy = 0;

const root = document.getElementById('app') as HTMLElement;

function setBusy(delta: number): void {
  busy += delta;
  document.body.classList.toggle('busy', busy > 0);
}

// ------------------------------------------------------------------ locations

let roots: string[] = [];

function relative(path: string): string {
  for (const r of roots) {
    const pre = r.endsWith('/') ? r : r + '/';
    if (path.startsWith(pre)) {
      return path.slice(pre.length);
    }
  }
  return path;
}

function locText(loc: Location): string {
  return `${relative(loc.path)}:${loc.line + 1}:${loc.col + 1}`;
}

function locLink(loc: Location | null, label?: string): HTMLElement {
  if (!loc) {
    return el('span', { class: 'muted' }, 'no location');
  }
  const a = el('a', { href: '#', class: 'loc', title: `show ${locText(loc)}` }, label ?? locText(loc));
  a.addEventListener('click', (ev) => {
    ev.preventDefault();
    void showLocation(loc);
  });
  return a;
}

async function showLocation(loc: Location): Promise<void> {
  if (t.reveal(loc)) {
    return;
  }
  try {
    const x = await t.request<Excerpt>('excerpt', { model: app?.model.model, path: loc.path, line: loc.line });
    const pre = el('div', { class: 'excerpt' });
    x.lines.forEach((line, i) => {
      const n = x.start + i;
      pre.append(el('div', { class: n === loc.line ? 'line target' : 'line' },
        el('span', { class: 'ln' }, String(n + 1).padStart(4, ' ')), '  ', line));
    });
    modal(`${x.relative}:${loc.line + 1}:${loc.col + 1}`, pre);
  } catch (e) {
    toast(`Cannot show ${locText(loc)}: ${(e as Error).message}`, 'error');
  }
}

// ------------------------------------------------------------------ toasts and modals

function toast(content: string | Node, kind: 'info' | 'error' | 'refusal' = 'info', sticky = false): HTMLElement {
  const box = document.getElementById('toasts') as HTMLElement;
  const close = el('button', { class: 'close', title: 'dismiss', 'aria-label': 'dismiss' }, '×');
  const item = el('div', { class: `toast ${kind}`, role: kind === 'info' ? 'status' : 'alert' }, content, close);
  close.addEventListener('click', () => item.remove());
  box.append(item);
  if (!sticky) {
    setTimeout(() => item.remove(), kind === 'error' ? 12000 : 7000);
  }
  return item;
}

function modal(title: string, body: Node): void {
  const close = el('button', { class: 'close', title: 'close', 'aria-label': 'close' }, '×');
  const dlg = el('div', { class: 'modal', role: 'dialog', 'aria-label': title },
    el('div', { class: 'modal-box' }, el('div', { class: 'modal-head' }, el('strong', {}, title), close), body));
  const done = () => dlg.remove();
  close.addEventListener('click', done);
  dlg.addEventListener('click', (ev) => ev.target === dlg && done());
  document.addEventListener('keydown', function esc(ev) {
    if (ev.key === 'Escape') {
      done();
      document.removeEventListener('keydown', esc);
    }
  });
  document.body.append(dlg);
}

function showRefusal(r: Refusal): void {
  document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
  const body = el('div', { class: 'refusal-body' },
    el('div', { class: 'refusal-msg' }, `${r.value ? 'Include' : 'Exclude'} ${r.feature}: refused.`));
  const mine = Object.entries(r.conflictsWith);
  if (mine.length) {
    body.append(el('div', {}, 'It conflicts with your decision' + (mine.length > 1 ? 's' : '') + ' to ' +
      mine.map(([f, v]) => `${v ? 'include' : 'exclude'} ${f}`).join(', ') + '.'));
  } else {
    body.append(el('div', {}, `No product ${r.value ? 'includes' : 'excludes'} ${r.feature}.`));
  }
  if (r.because.length) {
    const ul = el('ul', { class: 'because' });
    r.because.forEach((b) => ul.append(el('li', {}, b.label, ' ', b.location ? locLink(b.location) : null)));
    body.append(el('div', {}, 'Because:'), ul);
  }
  const item = toast(body, 'refusal', true);
  item.setAttribute('data-feature', r.feature);
  item.setAttribute('title', r.message);
}

// ------------------------------------------------------------------ header

function header(targets: Targets | null, m: ModelJson): HTMLElement {
  const picker = el('select', { id: 'model-picker', title: 'the feature model to configure' });
  const models = targets?.models ?? [{ model: m.model, launches: m.launches }];
  for (const x of models) {
    const o = el('option', { value: x.model }, relative(x.model) + (x.launches.length ? '' : ' (no launch file)'));
    if (x.model === m.model) {
      o.selected = true;
    }
    picker.append(o);
  }
  picker.addEventListener('change', () => void load(picker.value, targets));
  const search = el('input', {
    id: 'search', type: 'search', placeholder: 'Find a feature  ( / )', autocomplete: 'off', 'aria-label': 'find a feature',
  }) as HTMLInputElement;
  const results = el('ul', { id: 'search-results', role: 'listbox' });
  const runSearch = () => {
    results.replaceChildren();
    const found = app?.diagram.find(search.value) ?? [];
    for (const f of found) {
      const li = el('li', { role: 'option', 'data-feature': f.id }, f.name, el('span', { class: 'muted' }, ' ' + f.longName));
      li.addEventListener('mousedown', (ev) => {
        ev.preventDefault();
        pickFeature(f);
        results.replaceChildren();
      });
      results.append(li);
    }
  };
  const pickFeature = (f: FeatureNode) => {
    app?.diagram.reveal(f.id);
    showFeature(f);
  };
  search.addEventListener('input', runSearch);
  search.addEventListener('keydown', (ev) => {
    if (ev.key === 'Enter') {
      const first = app?.diagram.find(search.value, 1)[0];
      if (first) {
        pickFeature(first);
      }
      results.replaceChildren();
    } else if (ev.key === 'Escape') {
      results.replaceChildren();
    }
  });
  search.addEventListener('blur', () => setTimeout(() => results.replaceChildren(), 150));
  document.addEventListener('keydown', (ev) => {
    if (ev.key === '/' && document.activeElement !== search && !(ev.target as Element)?.closest?.('input,select,textarea')) {
      ev.preventDefault();
      search.focus();
    }
  });

  const reset = el('button', { id: 'reset', title: 'forget every decision' }, 'Reset');
  reset.addEventListener('click', () => void resetAll());
  const gen = el('div', { class: 'menu', id: 'generate-menu' });
  const genBtn = el('button', { id: 'generate', 'aria-haspopup': 'true' }, 'Generate ▾');
  const items = el('div', { class: 'menu-items', role: 'menu' });
  const modes: [string, string, string][] = [
    ['current', 'This product', 'the configuration launch file of the product you configured (every feature decided)'],
    ['completions', 'Every completion', 'one configuration launch file per remaining product'],
    ['sample', 'Pairwise sample', 'a sample of the remaining products covering every pair of feature choices'],
  ];
  for (const [mode, label, help] of modes) {
    const b = el('button', { role: 'menuitem', 'data-mode': mode, title: help }, label);
    b.addEventListener('click', () => {
      gen.classList.remove('open');
      void generate(mode);
    });
    items.append(b);
  }
  genBtn.addEventListener('click', () => gen.classList.toggle('open'));
  document.addEventListener('click', (ev) => {
    if (!gen.contains(ev.target as Node)) {
      gen.classList.remove('open');
    }
  });
  document.addEventListener('keydown', (ev) => {
    if (ev.key === 'Escape') {
      gen.classList.remove('open');
    }
  });
  gen.append(genBtn, items);

  const expand = el('button', { id: 'expand-all', title: 'expand the diagram (up to 400 features)' }, 'Expand');
  expand.addEventListener('click', () => app?.diagram.expandAll());
  const collapse = el('button', { id: 'collapse-all', title: 'collapse the diagram to the root' }, 'Collapse');
  collapse.addEventListener('click', () => app?.diagram.collapseAll());

  return el('header', {},
    el('div', { class: 'title' }, el('strong', {}, 'TVL configurator'), models.length > 1 ? picker : el('span', { class: 'muted' }, relative(m.model))),
    el('div', { id: 'count', 'aria-live': 'polite' },
      el('span', { id: 'remaining', 'data-remaining': '' }, '…'), ' of ',
      el('span', { id: 'total' }, '…'), ' products',
      el('span', { id: 'count-status', class: 'muted', 'data-state': 'pending' }, '')),
    el('div', { class: 'search' }, search, results),
    el('div', { class: 'actions' }, expand, collapse, reset, gen),
  );
}

// ------------------------------------------------------------------ details

function details(): HTMLElement {
  return document.getElementById('details') as HTMLElement;
}

function featureStatusText(id: string): string {
  const s = app?.state;
  if (!s) {
    return '';
  }
  if (id in s.decisions) {
    return s.decisions[id] ? 'included — your decision' : 'excluded — your decision';
  }
  if (id in s.implied) {
    return s.implied[id] ? 'included — implied by the model and your decisions' : 'excluded — implied by the model and your decisions';
  }
  return 'open';
}

function showFeature(f: FeatureNode): void {
  const d = details();
  const c = app?.counts;
  const n = c?.features[f.id];
  d.replaceChildren(
    el('h3', {}, f.name, el('span', { class: 'kind' }, ' feature')),
    el('dl', {},
      el('dt', {}, 'Name'), el('dd', {}, f.longName),
      el('dt', {}, 'Status'), el('dd', { 'data-field': 'status' }, featureStatusText(f.id)),
      el('dt', {}, 'Products'), el('dd', {}, n !== undefined && c?.remaining ? `in ${n} of ${c.remaining} remaining` : 'counting…'),
      el('dt', {}, 'Kind'), el('dd', {}, (f.optional ? 'optional' : 'mandatory') + (f.group ? `, group ${f.group.text} of ${f.children.length}` : '')),
      el('dt', {}, 'Declared'), el('dd', {}, locLink(f.location)),
      ...(f.constraints?.length ? [el('dt', {}, 'Constraints'), el('dd', {}, ...f.constraints.map((x) => el('code', { class: 'block' }, x)))] : []),
    ),
  );
}

function statusWords(st: string): string {
  return st === 'certain' ? 'in every remaining product' : st === 'possible' ? 'in some remaining products' : 'in no remaining product';
}

function showGraphItem(e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void {
  const d = details();
  const st = app?.graphStatus[e.id] ?? 'possible';
  if (kind === 'edge') {
    const x = e as GraphEdge;
    d.replaceChildren(
      el('h3', {}, `${x.kind}`, el('span', { class: 'kind' }, ' link')),
      el('dl', {},
        el('dt', {}, 'From'), el('dd', {}, x.source.replace(/^\w+:/, '')),
        el('dt', {}, 'To'), el('dd', {}, x.target.replace(/^\w+:/, '')),
        el('dt', {}, 'Condition'), el('dd', {}, x.condition ? el('code', {}, x.condition) : 'in every product'),
        el('dt', {}, 'Now'), el('dd', { 'data-field': 'status' }, statusWords(st)),
        el('dt', {}, 'Source'), el('dd', {}, locLink(x.location)),
      ),
    );
    return;
  }
  const x = e as GraphElement;
  const rows: (Node | string)[] = [
    el('dt', {}, 'Name'), el('dd', {}, x.name),
    el('dt', {}, 'Condition'), el('dd', { 'data-field': 'condition' }, x.condition ? el('code', {}, x.condition) : 'in every product'),
    el('dt', {}, 'Now'), el('dd', { 'data-field': 'status' }, statusWords(st)),
    el('dt', {}, 'Source'), el('dd', { 'data-field': 'location' }, locLink(x.location)),
  ];
  const det = x.details ?? {};
  for (const [k, v] of Object.entries(det)) {
    if (k === 'variants' && Array.isArray(v)) {
      const ul = el('ul', {});
      (v as { package: string; type: string; condition: string; location: Location | null }[]).forEach((r) =>
        ul.append(el('li', {}, el('code', {}, `${r.package}/${r.type}`), ' when ', el('code', {}, r.condition), ' ', locLink(r.location))));
      rows.push(el('dt', {}, 'Variants'), el('dd', {}, ul));
    } else if (k === 'remaps' && Array.isArray(v)) {
      if (v.length) {
        const ul = el('ul', {});
        (v as { from: string; to: string; condition: string; location: Location | null }[]).forEach((r) =>
          ul.append(el('li', {}, el('code', {}, `${r.from} → ${r.to}`), ' when ', el('code', {}, r.condition), ' ', locLink(r.location))));
        rows.push(el('dt', {}, 'Remaps'), el('dd', {}, ul));
      }
    } else if (v !== null && v !== undefined && v !== '') {
      rows.push(el('dt', {}, k[0].toUpperCase() + k.slice(1)), el('dd', {}, typeof v === 'string' ? v : JSON.stringify(v)));
    }
  }
  const links = (app?.graphJson?.edges ?? []).filter((l) => l.source === x.id || l.target === x.id);
  if (links.length) {
    const ul = el('ul', { 'data-field': 'links' });
    for (const l of links) {
      const other = l.source === x.id ? l.target : l.source;
      const lst = app?.graphStatus[l.id] ?? 'possible';
      ul.append(el('li', { class: `st-${lst}` }, `${l.kind} `, el('code', {}, other.replace(/^\w+:/, '')),
        l.condition ? el('span', { class: 'muted' }, ` when ${l.condition}`) : null));
    }
    rows.push(el('dt', {}, x.kind === 'node' ? 'Topics / params' : 'Used by'), el('dd', {}, ul));
  }
  d.replaceChildren(el('h3', {}, x.label, el('span', { class: 'kind' }, ` ${x.kind}`)), el('dl', {}, ...rows));
}

// ------------------------------------------------------------------ problems

function renderProblems(force = true): void {
  const a = app;
  const box = document.getElementById('problems') as HTMLElement;
  if (!a) {
    return;
  }
  // a click that changes no problem's status does not redraw the list (hundreds on big models)
  const key = JSON.stringify([a.problems?.length ?? -1, a.problemStatus, a.showRuledOut, a.showAllProblems]);
  if (!force && key === problemsKey) {
    return;
  }
  problemsKey = key;
  if (a.problems === null) {
    box.replaceChildren(el('div', { class: 'panel-head' }, el('strong', {}, 'Problems'),
      el('span', { class: 'muted', id: 'problem-count', 'data-checking': 'true' }, ' checking the model and its launch files…')));
    return;
  }
  const shown: Problem[] = [];
  const ruledOut: Problem[] = [];
  for (const p of a.problems) {
    const st = a.problemStatus[p.id] ?? 'certain';
    (st === 'excluded' ? ruledOut : shown).push(p);
  }
  const list = el('ul', { class: 'problem-list' });
  const item = (p: Problem, out: boolean) => {
    const st = a.problemStatus[p.id];
    const li = el('li', { class: `problem sev-${p.severity}${out ? ' ruled-out' : ''}`, 'data-code': p.code, 'data-status': st },
      el('span', { class: `sev sev-${p.severity}`, title: p.severity }, p.severity[0].toUpperCase()),
      el('span', { class: 'code' }, p.code),
      el('span', { class: 'msg' }, p.message),
      p.location ? locLink(p.location) : null,
      st === 'possible' ? el('span', { class: 'tag', title: p.condition ? `when ${p.condition}` : 'in some products' }, 'in some products') : null,
      out ? el('span', { class: 'tag' }, 'ruled out by your decisions') : null,
    );
    list.append(li);
  };
  const listed = [...shown.map((p) => [p, false] as const), ...(a.showRuledOut ? ruledOut.map((p) => [p, true] as const) : [])];
  const limit = a.showAllProblems ? listed.length : PROBLEMS_SHOWN;
  listed.slice(0, limit).forEach(([p, out]) => item(p, out));
  if (listed.length > limit) {
    const more = el('button', { class: 'more-problems' }, `show all ${listed.length}`);
    more.addEventListener('click', () => {
      a.showAllProblems = true;
      renderProblems();
    });
    list.append(el('li', { class: 'problem' }, more));
  }
  const toggle = el('label', { class: 'toggle' });
  const cb = el('input', { type: 'checkbox', id: 'show-ruled-out' }) as HTMLInputElement;
  cb.checked = a.showRuledOut;
  cb.addEventListener('change', () => {
    a.showRuledOut = cb.checked;
    renderProblems();
  });
  toggle.append(cb, ` show ${ruledOut.length} ruled out`);
  box.replaceChildren(
    el('div', { class: 'panel-head' },
      el('strong', {}, 'Problems'),
      el('span', { id: 'problem-count', 'data-shown': String(shown.length), 'data-ruled-out': String(ruledOut.length) },
        ` ${shown.length} can still occur` + (ruledOut.length ? `, ${ruledOut.length} ruled out by your decisions` : '')),
      ruledOut.length ? toggle : null),
    shown.length || a.showRuledOut ? list : el('div', { class: 'muted empty-problems' }, 'No problem can occur in the remaining products.'),
  );
}

// ------------------------------------------------------------------ state and counts

function applyState(state: State): void {
  if (!app) {
    return;
  }
  app.state = state;
  if (state.problems) {
    app.problemStatus = state.problems;
  }
  app.diagram.setState(state);
  renderProblems(false);
  if (state.graph) {
    app.graphStatus = state.graph;
    void app.graph?.setStatus(state.graph);
  }
  const gen = document.querySelector('[data-mode="current"]') as HTMLButtonElement | null;
  if (gen) {
    gen.disabled = !state.complete;
    gen.title = state.complete ? 'the configuration launch file of this product'
      : `decide the ${state.open.length} open feature(s) first (or generate every completion)`;
  }
  document.body.dataset.complete = String(state.complete);
}

function sleep(ms: number): Promise<void> {
  return new Promise((resolve) => setTimeout(resolve, ms));
}

/** The count status line: data-state is pending (asked), compiling (the model is being compiled
 * in the background: no counts yet), ready (counts shown) or failed. */
function countStatus(state: string, text: string, title = ''): void {
  const s = document.getElementById('count-status') as HTMLElement | null;
  if (s) {
    s.dataset.state = state;
    s.textContent = text;
    s.title = title;
  }
  document.body.dataset.counts = state;
}

async function refreshCounts(): Promise<void> {
  const a = app;
  if (!a) {
    return;
  }
  const seq = ++countSeq;
  const visible = a.diagram.visibleIds();
  const shown = new Set(visible);
  const order = [...visible, ...a.diagram.allIds().filter((x) => !shown.has(x))];
  const rem = document.getElementById('remaining') as HTMLElement;
  rem.classList.add('pending');
  countStatus('pending', '');
  a.diagram.setCounts(a.counts ? { ...a.counts, features: {} } : null);
  // the model compiles in the background on first use: the server answers "pending" at once
  // and we ask again, sooner at first (small models are ready in a few milliseconds)
  let delay = 100;
  try {
    for (;;) {
      const c = await t.request<Counts>('counts', { model: a.model.model, features: order, timeout: 20, wait: 0 });
      if (seq !== countSeq || app !== a) {
        return;
      }
      if (c.pending) {
        const secs = c.seconds ? ` ${Math.round(c.seconds)} s` : '';
        countStatus('compiling', ` · compiling the model for counting…${secs}`, c.message ?? '');
        a.diagram.setCounts({ ...c, features: {} });
        await sleep(delay);
        delay = Math.min(1500, delay * 1.6);
        if (seq !== countSeq || app !== a) {
          return;
        }
        continue;
      }
      a.counts = c;
      a.diagram.setCounts(c);
      rem.textContent = formatCount(c.remaining);
      rem.title = c.remaining ?? 'no answer in time';
      rem.dataset.remaining = c.remaining ?? '';
      const tot = document.getElementById('total') as HTMLElement;
      tot.textContent = formatCount(c.total);
      tot.title = c.total ?? '';
      rem.classList.remove('pending');
      if (c.remaining === null) {
        countStatus('failed', ' · not counted', c.message ?? '');
      } else {
        countStatus('ready', c.complete ? '' : ' · some features not counted in time',
          c.engine ? `counted by ${c.engine}${c.message ? ` (${c.message})` : ''}` : '');
      }
      return;
    }
  } catch (e) {
    if (seq === countSeq) {
      rem.classList.remove('pending');
      countStatus('failed', ' · counting failed', (e as Error).message);
      toast(`Counting failed: ${(e as Error).message}`, 'error');
    }
  }
}

async function loadGraph(a: App, box: HTMLElement): Promise<void> {
  const wait = el('div', { class: 'empty' }, 'Building the computation graph of every product…');
  box.append(wait);
  try {
    const g = await t.request<GraphJson>('graph', { model: a.model.model });
    if (app !== a) {
      return;
    }
    wait.remove();
    a.graphJson = g;
    a.graph = new GraphView(box, g, { select: (e, k) => showGraphItem(e, k) }, () => t.layoutWorker());
    // the decisions may have changed meanwhile: the latest state has the statuses
    const st = a.state.graph ? a.state : await t.request<State>('state', { model: a.model.model });
    if (app !== a) {
      return;
    }
    a.graphStatus = st.graph ?? g.status ?? {};
    await a.graph.setStatus(a.graphStatus);
    document.body.dataset.graph = 'ready';
  } catch (e) {
    wait.textContent = `No computation graph: ${(e as Error).message}`;
  }
}

async function loadProblems(a: App): Promise<void> {
  try {
    const r = await t.request<ProblemsJson>('problems', { model: a.model.model });
    if (app !== a) {
      return;
    }
    a.problems = r.problems;
    a.problemStatus = r.status ?? {};
    // the decisions may have changed while the files were checked
    applyState(await t.request<State>('state', { model: a.model.model }));
    document.body.dataset.problems = 'ready';
  } catch (e) {
    if (app === a) {
      a.problems = [];
      renderProblems();
      toast(`Checking the files failed: ${(e as Error).message}`, 'error');
    }
  }
}

async function decide(feature: string, value: boolean | null): Promise<void> {
  const a = app;
  if (!a) {
    return;
  }
  setBusy(1);
  try {
    const r = await t.request<DecideResult>('decide', { model: a.model.model, feature, value });
    applyState(r.state);
    if (r.refused) {
      showRefusal(r.refused);
    } else {
      document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
      void refreshCounts();
    }
  } catch (e) {
    toast((e as Error).message, 'error');
  } finally {
    setBusy(-1);
  }
}

async function resetAll(): Promise<void> {
  const a = app;
  if (!a) {
    return;
  }
  setBusy(1);
  try {
    const r = await t.request<DecideResult>('reset', { model: a.model.model });
    applyState(r.state);
    document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
    void refreshCounts();
  } catch (e) {
    toast((e as Error).message, 'error');
  } finally {
    setBusy(-1);
  }
}

async function generate(mode: string): Promise<void> {
  const a = app;
  if (!a) {
    return;
  }
  setBusy(1);
  try {
    const r = await t.request<GenerateResult>('generate', { model: a.model.model, mode });
    const files = r.written ?? r.files.map((f) => f.path);
    const ul = el('ul', { class: 'files' });
    files.slice(0, 12).forEach((f) => ul.append(el('li', { 'data-path': f }, relative(f))));
    if (files.length > 12) {
      ul.append(el('li', { class: 'muted' }, `… and ${files.length - 12} more`));
    }
    const t1 = el('div', { class: 'generated', 'data-count': String(files.length) },
      files.length ? `Wrote ${files.length} configuration launch file${files.length > 1 ? 's' : ''} to ${relative(r.folder)}:` : 'No product to write.', ul);
    toast(t1, 'info', true);
  } catch (e) {
    toast(`Generate: ${(e as Error).message}`, 'error');
  } finally {
    setBusy(-1);
  }
}

// ------------------------------------------------------------------ loading

function legend(): HTMLElement {
  const item = (cls: string, label: string) => el('span', { class: `legend-item ${cls}` }, el('i', {}), label);
  return el('div', { class: 'legend' },
    item('st-user-in', 'included (you)'), item('st-implied-in', 'included (implied)'),
    item('st-user-out', 'excluded (you)'), item('st-implied-out', 'excluded (implied)'), item('st-open', 'open'),
    el('span', { class: 'legend-item' }, el('b', { class: 'dot mandatory' }), 'mandatory'),
    el('span', { class: 'legend-item' }, el('b', { class: 'dot optional' }), 'optional'),
    el('span', { class: 'legend-item', title: 'a hollow arc: exactly one child (oneOf); a filled arc: at least one (someOf)' }, 'arcs: oneOf hollow, someOf filled'));
}

function graphLegend(): HTMLElement {
  const item = (cls: string, label: string) => el('span', { class: `legend-item g-${cls}` }, el('i', {}), label);
  const cb = el('input', { type: 'checkbox', id: 'show-removed' }) as HTMLInputElement;
  cb.addEventListener('change', () => {
    if (app?.graph) {
      app.graph.showRemoved = cb.checked;
      app.graph.restyle();
    }
  });
  return el('div', { class: 'legend' }, item('node', 'node'), item('topic', 'topic'), item('param', 'parameter'),
    item('service', 'service'), el('span', { class: 'legend-item g-dashed' }, el('i', {}), 'in some products'),
    el('label', { class: 'toggle' }, cb, ' show removed'));
}

async function load(modelPath?: string | null, targets?: Targets | null): Promise<void> {
  root.classList.add('loading');
  try {
    if (targets === undefined) {
      targets = t.kind === 'http' ? await t.request<Targets>('targets') : null;
      modelPath = modelPath ?? targets?.initial ?? undefined;
    }
    const m = await t.request<ModelJson>('model', modelPath ? { model: modelPath } : {});
    roots = m.roots;
    root.classList.remove('loading');
    root.replaceChildren();
    const diagramBox = el('section', { id: 'diagram', 'aria-label': 'feature diagram' });
    const graphBox = el('section', { id: 'graph', 'aria-label': 'computation graph' });
    const side = el('div', { id: 'side' },
      el('div', { class: 'panel-head' }, el('strong', {}, 'Computation graph'),
        el('span', { class: 'muted' }, m.launch ? ' ' + basename(m.launch) : ''), graphLegend()),
      graphBox, el('section', { id: 'details', 'aria-label': 'details' },
        el('div', { class: 'muted' }, 'Select a feature or a graph element to see its condition, source and links.')));
    const main = el('main', {}, el('div', { id: 'left' },
      el('div', { class: 'panel-head' }, el('strong', {}, 'Feature diagram'),
        el('span', { class: 'muted' }, ` ${m.name} · ${m.features} features`), legend()), diagramBox), side);
    root.append(header(targets ?? null, m), main, el('section', { id: 'problems', 'aria-label': 'problems' }),
      el('div', { id: 'toasts', 'aria-live': 'polite' }));
    // app must exist before the views call back into it
    const a: App = {
      model: m, state: m.state, counts: null, diagram: null as unknown as Diagram, graph: null, graphJson: null,
      graphStatus: {}, showRuledOut: false, showAllProblems: false, problems: null, problemStatus: {},
    };
    app = a;
    a.diagram = new Diagram(diagramBox, m.tree, {
      decide: (f, v) => void decide(f, v),
      select: (f) => showFeature(f),
    });
    applyState(m.state);
    document.body.dataset.ready = 'diagram';
    void refreshCounts();
    void loadGraph(a, graphBox);
    void loadProblems(a);
  } catch (e) {
    root.classList.remove('loading');
    root.replaceChildren(el('div', { class: 'fatal' }, el('h2', {}, 'The configurator cannot open this workspace'),
      el('p', {}, (e as Error).message)));
  }
}

t.onRefresh((reload) => {
  if (!app || reload) {
    void load();
    return;
  }
  void (async () => {
    const s = await t.request<State>('state', { model: app?.model.model });
    applyState(s);
    void refreshCounts();
  })();
});

void load();
