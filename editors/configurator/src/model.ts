// The feature tree as both views use it: an index by id, parents, search, and the status of a
// feature under the current state (your decision, implied, open).
import type { Counts, FeatureNode, State } from './types';

export type FeatureStatus = 'user-in' | 'user-out' | 'implied-in' | 'implied-out' | 'open';

export const STATUS_WORDS: Record<FeatureStatus, string> = {
  'user-in': 'included (your decision)',
  'user-out': 'excluded (your decision)',
  'implied-in': 'included (implied)',
  'implied-out': 'excluded (implied)',
  open: 'open',
};

export function statusOf(state: State | null, id: string): FeatureStatus {
  if (!state) {
    return 'open';
  }
  if (id in state.decisions) {
    return state.decisions[id] ? 'user-in' : 'user-out';
  }
  if (id in state.implied) {
    return state.implied[id] ? 'implied-in' : 'implied-out';
  }
  return 'open';
}

/** What a click on "include" (want = true) or "exclude" does: your own decision again undoes it. */
export function nextValue(st: FeatureStatus, want: boolean): boolean | null {
  if ((st === 'user-in' && want) || (st === 'user-out' && !want)) {
    return null;
  }
  return want;
}

export class FeatureIndex {
  readonly byId = new Map<string, FeatureNode>();
  readonly parentOf = new Map<string, string>();
  readonly order: FeatureNode[] = []; // preorder, each feature once

  constructor(readonly root: FeatureNode) {
    const stack: [FeatureNode, FeatureNode | null][] = [[root, null]];
    while (stack.length) {
      const [n, parent] = stack.pop() as [FeatureNode, FeatureNode | null];
      if (n.ref || this.byId.has(n.id)) {
        continue;
      }
      this.byId.set(n.id, n);
      this.order.push(n);
      if (parent) {
        this.parentOf.set(n.id, parent.id);
      }
      for (let i = n.children.length - 1; i >= 0; i--) {
        stack.push([n.children[i], n]);
      }
    }
  }

  get size(): number {
    return this.byId.size;
  }

  /** Ancestors of a feature, the root first. */
  ancestors(id: string): string[] {
    const out: string[] = [];
    let p = this.parentOf.get(id);
    while (p) {
      out.unshift(p);
      p = this.parentOf.get(p);
    }
    return out;
  }

  /** Features whose name starts with the query, then those whose long name contains it. */
  find(query: string, limit = 20): FeatureNode[] {
    const q = query.trim().toLowerCase();
    if (!q) {
      return [];
    }
    const exact: FeatureNode[] = [];
    const starts: FeatureNode[] = [];
    const contains: FeatureNode[] = [];
    for (const f of this.order) {
      const n = f.name.toLowerCase();
      if (n === q) {
        exact.push(f);
      } else if (n.startsWith(q)) {
        starts.push(f);
      } else if (f.longName.toLowerCase().includes(q)) {
        contains.push(f);
      }
      if (exact.length + starts.length >= limit) {
        break;
      }
    }
    return [...exact, ...starts, ...contains].slice(0, limit);
  }
}

export interface FeatureViewHandlers {
  decide(feature: string, value: boolean | null): void;
  select(feature: FeatureNode): void;
  /** the features drawn changed (counts are asked for the ones shown) */
  shown(): void;
}

/** What the page asks of the diagram and of the tree alike. */
export interface FeatureView {
  readonly kind: 'diagram' | 'tree';
  setState(state: State): void;
  setCounts(counts: Counts | null): void;
  /** features currently on screen (their counts are asked for first) */
  visibleIds(): string[];
  /** expand its ancestors, bring it into view and mark it selected */
  reveal(id: string): void;
  /** mark it selected (no scrolling) */
  select(id: string | null): void;
  /** features linked to the selected graph element */
  setLinked(ids: Set<string>): void;
  expandAll(): void;
  collapseAll(): void;
  focus(): void;
  destroy(): void;
}
