//! The contact graph of large bodies in compressed rows, and the terminals of
//! a chain problem along one axis.

/// An undirected graph in compressed rows, each edge stored both ways with the
/// periodic image offset of the far node (`[0, 0]` with walls).
#[derive(Clone, Debug, Default)]
pub struct LinkGraph {
    /// `adj[row[u]..row[u + 1]]` are the neighbours of `u`.
    pub row: Vec<usize>,
    /// Neighbour node of each edge.
    pub adj: Vec<u32>,
    /// Image offset of the neighbour along the horizontal axes.
    pub offset: Vec<[i32; 2]>,
}

impl LinkGraph {
    /// A graph of `n` nodes from undirected edges `(u, v, offset of v seen from u)`.
    /// Each row is sorted by neighbour and offset, without repeats.
    pub fn from_edges(n: usize, edges: &[(u32, u32, [i32; 2])]) -> Self {
        // Bucketed by node (a counting sort), then each short row sorted on its
        // own: a sort of all 2m directed edges was most of the graph's cost on a
        // bed of 10^6 spheres.
        let looped = |&(u, v, o): &(u32, u32, [i32; 2])| u == v && o == [0, 0];
        let mut fill = vec![0usize; n + 1];
        for e in edges.iter().filter(|e| !looped(e)) {
            fill[e.0 as usize + 1] += 1;
            fill[e.1 as usize + 1] += 1;
        }
        for i in 0..n {
            fill[i + 1] += fill[i];
        }
        let bucket = fill.clone();
        let mut slots = vec![(0u32, [0i32; 2]); fill[n]];
        for &(u, v, o) in edges.iter().filter(|e| !looped(e)) {
            slots[fill[u as usize]] = (v, o);
            fill[u as usize] += 1;
            slots[fill[v as usize]] = (u, [-o[0], -o[1]]);
            fill[v as usize] += 1;
        }
        let mut row = Vec::with_capacity(n + 1);
        row.push(0usize);
        let mut adj = Vec::with_capacity(slots.len());
        let mut offset = Vec::with_capacity(slots.len());
        for u in 0..n {
            let list = &mut slots[bucket[u]..bucket[u + 1]];
            list.sort_unstable();
            let mut last = None;
            for &(v, o) in list.iter() {
                if last != Some((v, o)) {
                    adj.push(v);
                    offset.push(o);
                    last = Some((v, o));
                }
            }
            row.push(adj.len());
        }
        LinkGraph { row, adj, offset }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.row.len().saturating_sub(1)
    }

    /// Edge indices of node `u`.
    #[inline]
    pub(super) fn edges(&self, u: usize) -> std::ops::Range<usize> {
        self.row[u]..self.row[u + 1]
    }
}

/// The chain problem along one axis: which nodes may start and end a chain, and
/// which edges a chain may use.
#[derive(Clone, Debug)]
pub struct Terminals {
    /// Nodes touching the low wall (or the seam from the right).
    pub start: Vec<bool>,
    /// Nodes touching the high wall (or the seam from the left).
    pub end: Vec<bool>,
    /// Axis whose seam edges are cut (periodic), `None` with walls.
    pub seam: Option<usize>,
}

impl Terminals {
    /// Whether a chain may use edge `e` (not across the seam).
    #[inline]
    pub(super) fn usable(&self, g: &LinkGraph, e: usize) -> bool {
        self.seam.is_none_or(|k| g.offset[e][k] == 0)
    }
}
