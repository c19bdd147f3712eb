// The details panel: what is selected (a feature, a graph element or link), refreshed after every
// decision and every count -- never stale. Counts are written as in the header (4.42 × 10⁹⁷),
// the exact digits one click away; an implied state says which of your decisions implied it and
// which parts of the model made it so.
import { conditionNames, countPhrase, el, exactCount, formatCount } from './format';
import type { Page } from './page';
import { STATUS_WORDS, statusOf } from './model';
import type { Explanation, FeatureNode, GraphEdge, GraphElement, Location } from './types';
import { locLink } from './ui';

function box(): HTMLElement {
  return document.getElementById('details') as HTMLElement;
}

/** A count written as in the header, with a button showing every digit. */
export function countWithExact(n: string | null | undefined, suffix = ''): HTMLElement {
  const span = el('span', { class: 'count-text' }, formatCount(n) + suffix);
  if (!n || n.length <= 12) {
    return span;
  }
  const exact = el('code', { class: 'exact', hidden: '' }, exactCount(n));
  const btn = el('button', { class: 'link-btn exact-btn', title: `all ${n.length} digits` }, 'exact');
  btn.addEventListener('click', () => {
    exact.hidden = !exact.hidden;
    btn.textContent = exact.hidden ? 'exact' : 'hide digits';
  });
  return el('span', {}, span, ' ', btn, exact);
}

function decisionButtons(page: Page, f: FeatureNode): HTMLElement {
  const st = statusOf(page.state, f.id);
  const b = (label: string, cls: string, value: boolean | null, title: string) => {
    const x = el('button', { class: `small ${cls}`, title }, label);
    x.addEventListener('click', () => page.decide(f.id, value));
    return x;
  };
  const out = el('div', { class: 'decide-row' });
  if (st !== 'user-in') out.append(b('Include', 'inc', true, `include ${f.name}`));
  if (st !== 'user-out') out.append(b('Exclude', 'exc', false, `exclude ${f.name}`));
  if (st === 'user-in' || st === 'user-out') out.append(b('Undo', 'undo', null, `forget your decision about ${f.name}`));
  return out;
}

export function renderFeature(page: Page, f: FeatureNode): void {
  const d = box();
  const st = statusOf(page.state, f.id);
  const c = page.counts;
  const n = c?.features[f.id];
  const why = el('dd', { 'data-field': 'status' }, STATUS_WORDS[st]);
  if (st === 'implied-in' || st === 'implied-out') {
    why.append(el('span', { class: 'muted' }, ' …'));
    void page.explain(f.id).then((x: Explanation | null) => {
      if (!x || page.selection?.id !== f.id) {
        return;
      }
      why.replaceChildren(explanation(page, x));
    });
  }
  let products: HTMLElement;
  if (n !== undefined && c?.remaining) {
    products = el('dd', { 'data-field': 'products' }, countWithExact(n), ` of ${formatCount(c.remaining)} remaining`,
      el('span', { class: 'muted' }, ` (${countPhrase(n, c.remaining).replace(/^.*\(/, '').replace(/\)$/, '')})`));
  } else {
    products = el('dd', { 'data-field': 'products', class: 'muted' }, page.countNote());
  }
  const group = f.group ? `${f.group.text}, ${f.children.length} ${f.children.length === 1 ? 'child' : 'children'}` : '';
  const links = page.graphLinksOf(f.id);
  const rows: (Node | null)[] = [
    el('dt', {}, 'Status'), why,
    el('dt', {}, 'Products'), products,
    el('dt', {}, 'Kind'), el('dd', { 'data-field': 'kind' }, f.kindText ?? (f.optional ? 'optional' : 'mandatory')),
  ];
  if (group) rows.push(el('dt', {}, 'Group'), el('dd', { 'data-field': 'group' }, group));
  if (f.longName !== f.name) rows.push(el('dt', {}, 'Full name'), el('dd', {}, f.longName));
  rows.push(el('dt', {}, 'Declared'), el('dd', {}, locLink(f.location)));
  if (f.constraints?.length) {
    rows.push(el('dt', {}, 'Constraints'), el('dd', {}, ...f.constraints.map((x) => el('code', { class: 'block' }, x))));
  }
  if (links.length) {
    const ul = el('ul', { 'data-field': 'graph-links', class: 'chips' });
    for (const e of links.slice(0, 30)) {
      const a = el('a', { href: '#', class: `chip g-${e.kind} st-${page.graphStatus[e.id] ?? 'possible'}`, title: e.condition ?? '' },
        `${e.kind} ${e.label}`);
      a.addEventListener('click', (ev) => {
        ev.preventDefault();
        page.selectGraph(e.id);
      });
      ul.append(el('li', {}, a));
    }
    if (links.length > 30) ul.append(el('li', { class: 'muted' }, `… ${links.length - 30} more`));
    rows.push(el('dt', {}, 'Switches'), el('dd', {}, ul));
  }
  d.replaceChildren(
    el('h3', {}, f.name, el('span', { class: 'kind' }, ' feature')),
    decisionButtons(page, f),
    el('dl', {}, ...rows),
  );
  d.dataset.selected = f.id;
}

function explanation(page: Page, x: Explanation): HTMLElement {
  const verb = x.value ? 'included' : 'excluded';
  const out = el('span', { class: 'why', 'data-why': x.text });
  const mine = Object.entries(x.byDecisions);
  if (mine.length) {
    out.append(`${verb} because you `);
    mine.forEach(([k, v], i) => {
      if (i) out.append(' and ');
      const a = el('a', { href: '#', class: 'feature-link', 'data-feature': k, title: `show ${k}` }, k);
      a.addEventListener('click', (ev) => {
        ev.preventDefault();
        page.revealFeature(k);
      });
      out.append(`${v ? 'included' : 'excluded'} `, a);
    });
  } else {
    out.append(`${verb} in every product of the model`);
  }
  if (x.because.length) {
    out.append(': ');
    x.because.forEach((b, i) => {
      if (i) out.append('; ');
      out.append(b.location ? locLink(b.location, b.label) : b.label);
    });
  }
  return out;
}

function statusWords(st: string): string {
  return st === 'certain' ? 'in every remaining product' : st === 'possible' ? 'in some remaining products' : 'in no remaining product';
}

function featureChips(page: Page, cond: string | null): HTMLElement | null {
  const names = conditionNames(cond).filter((n) => page.index.byId.has(n));
  if (!names.length) {
    return null;
  }
  const ul = el('ul', { class: 'chips', 'data-field': 'features' });
  for (const n of names) {
    const st = statusOf(page.state, n);
    const a = el('a', { href: '#', class: `chip st-${st}`, title: `${n}: ${STATUS_WORDS[st]}`, 'data-feature': n }, n);
    a.addEventListener('click', (ev) => {
      ev.preventDefault();
      page.revealFeature(n);
    });
    ul.append(el('li', {}, a));
  }
  return ul;
}

export function renderGraphItem(page: Page, e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void {
  const d = box();
  d.dataset.selected = e.id;
  const st = page.graphStatus[e.id] ?? 'possible';
  if (kind === 'edge') {
    const x = e as GraphEdge;
    const chips = featureChips(page, x.condition);
    d.replaceChildren(
      el('h3', {}, `${x.kind}`, el('span', { class: 'kind' }, ' link')),
      el('dl', {},
        el('dt', {}, 'From'), el('dd', {}, x.source.replace(/^\w+:/, '')),
        el('dt', {}, 'To'), el('dd', {}, x.target.replace(/^\w+:/, '')),
        el('dt', {}, 'Condition'), el('dd', { 'data-field': 'condition' }, x.condition ? el('code', {}, x.condition) : 'in every product'),
        ...(chips ? [el('dt', {}, 'Features'), el('dd', {}, chips)] : []),
        el('dt', {}, 'Now'), el('dd', { 'data-field': 'status' }, statusWords(st)),
        el('dt', {}, 'Source'), el('dd', {}, locLink(x.location)),
      ),
    );
    return;
  }
  const x = e as GraphElement;
  const chips = featureChips(page, x.condition);
  const rows: (Node | string)[] = [
    el('dt', {}, 'Name'), el('dd', {}, x.name),
    el('dt', {}, 'Condition'), el('dd', { 'data-field': 'condition' }, x.condition ? el('code', {}, x.condition) : 'in every product'),
  ];
  if (chips) rows.push(el('dt', {}, 'Features'), el('dd', {}, chips));
  rows.push(
    el('dt', {}, 'Now'), el('dd', { 'data-field': 'status' }, statusWords(st)),
    el('dt', {}, 'Source'), el('dd', { 'data-field': 'location' }, locLink(x.location)),
  );
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
  const links = (page.graphJson?.edges ?? []).filter((l) => l.source === x.id || l.target === x.id);
  if (links.length) {
    const ul = el('ul', { 'data-field': 'links' });
    for (const l of links) {
      const other = l.source === x.id ? l.target : l.source;
      const lst = page.graphStatus[l.id] ?? 'possible';
      const a = el('a', { href: '#' }, el('code', {}, other.replace(/^\w+:/, '')));
      a.addEventListener('click', (ev) => {
        ev.preventDefault();
        page.selectGraph(other);
      });
      ul.append(el('li', { class: `st-${lst}` }, `${l.kind} `, a,
        l.condition ? el('span', { class: 'muted' }, ` when ${l.condition}`) : null));
    }
    rows.push(el('dt', {}, x.kind === 'node' ? 'Topics / params' : 'Used by'), el('dd', {}, ul));
  }
  const label = x.kind === 'include' ? 'include, not followed' : x.kind;
  d.replaceChildren(el('h3', {}, x.label, el('span', { class: 'kind' }, ` ${label}`)), el('dl', {}, ...rows));
}

export function renderNothing(): void {
  const d = box();
  delete d.dataset.selected;
  d.replaceChildren(el('div', { class: 'muted' },
    'Select a feature (click it, or find it with / ) or a graph element to see its status, why, its count and what it switches.'));
}
