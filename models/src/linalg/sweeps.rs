//! The two triangular sweeps of a solve with a simplicial Cholesky factor A = L Lᵀ (in the
//! factor's own numbering): L y = b by columns, scattering each solved entry into the rows
//! below it, then Lᵀ x = y by columns in reverse, gathering each entry from the rows below.
//!
//! These replace faer's simplicial solve, because the solve is most of a full-order implicit
//! step and faer's sweeps go one column at a time: every stored entry costs a load of its
//! row index, of its value and of x_i (and a store of x_i going forward), and the backward
//! sweep sums each column into one accumulator (a chain of dependent adds). Here:
//!
//! - columns are swept in **panels** of up to four consecutive columns j, j+1, … whose
//!   patterns below the panel are the same (column j+k holds the rows of column j from its
//!   k-th entry on — the two dofs of a node of a 2D mesh usually form one), so a row index
//!   and x_i are loaded (and stored) once for the panel's two to four values;
//! - the panel's values are copied after each factorization into one array in the order the
//!   sweeps read them (its triangle, then for each row below it the panel's values side by
//!   side), and its row indices are stored once: two streams per panel instead of one per
//!   column;
//! - the backward sums run in several independent partial sums;
//! - the pivots are inverted once per factorization, and indices are 32-bit.
//!
//! Measured on the default abdomen: see BENCHMARKS.md, "Full-order step".

/// Widest panel swept at once.
const MAX_PANEL: usize = 4;

/// A simplicial factor laid out by panels for the sweeps.
#[derive(Debug, Clone, Default)]
pub(super) struct Sweeps {
    panels: Vec<Panel>,
    /// The rows below each panel.
    rows: Vec<u32>,
    /// Each panel's triangle L_{j+a, j+b} (a > b, by b then a), then for each row below it
    /// the panel's values side by side.
    values: Vec<f64>,
    /// The position in faer's column storage of each of `values`.
    source: Vec<u32>,
    /// Position of each pivot L_jj in faer's column storage, and 1 / L_jj.
    pivots: Vec<u32>,
    inv_diag: Vec<f64>,
}

/// A panel: columns `column .. column + width`, its rows and values from `rows` and `values`
/// of [`Sweeps`].
#[derive(Debug, Clone, Copy)]
struct Panel {
    column: u32,
    width: u32,
    /// Start in `rows` and number of rows below the panel.
    rows: u32,
    len: u32,
    /// Start in `values`.
    values: u32,
}

impl Sweeps {
    /// The layout for a simplicial factor's pattern (column pointers, row indices with the
    /// diagonal first in every column). Column j + k joins the panel starting at j when its
    /// rows are those of column j from the k-th entry on.
    pub fn new(col_ptr: &[u32], row_idx: &[u32]) -> Self {
        let n = col_ptr.len() - 1;
        let rows = |j: usize| &row_idx[col_ptr[j] as usize..col_ptr[j + 1] as usize];
        let mut s = Self {
            pivots: col_ptr[..n].to_vec(),
            inv_diag: vec![0.0; n],
            ..Self::default()
        };
        let mut j = 0;
        while j < n {
            let mut width = 1;
            while width < MAX_PANEL
                && j + width < n
                && rows(j).get(width..) == Some(rows(j + width))
            {
                width += 1;
            }
            s.push_panel(col_ptr, &rows(j)[width..], j, width);
            j += width;
        }
        s.values = vec![0.0; s.source.len()];
        s
    }

    fn push_panel(&mut self, col_ptr: &[u32], below: &[u32], j: usize, width: usize) {
        self.panels.push(Panel {
            column: j as u32,
            width: width as u32,
            rows: self.rows.len() as u32,
            len: below.len() as u32,
            values: self.source.len() as u32,
        });
        self.rows.extend_from_slice(below);
        let start = |b: usize| col_ptr[j + b];
        for b in 0..width {
            self.source
                .extend((1..width - b).map(|k| start(b) + k as u32));
        }
        for t in 0..below.len() {
            self.source
                .extend((0..width).map(|b| start(b) + (width - b + t) as u32));
        }
    }

    /// The width of every panel, in order.
    #[cfg(test)]
    pub fn widths(&self) -> Vec<u32> {
        self.panels.iter().map(|p| p.width).collect()
    }

    /// Takes the values of a new numeric factorization (faer's column storage).
    pub fn load(&mut self, l_values: &[f64]) {
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = l_values[k as usize];
        }
        for (d, &k) in self.inv_diag.iter_mut().zip(&self.pivots) {
            *d = 1.0 / l_values[k as usize];
        }
    }

    /// Solves L Lᵀ x = b in place (`x` holds b on entry).
    pub fn solve(&self, x: &mut [f64]) {
        for p in &self.panels {
            match p.width {
                1 => self.forward::<1>(p, x),
                2 => self.forward::<2>(p, x),
                3 => self.forward::<3>(p, x),
                _ => self.forward::<4>(p, x),
            }
        }
        for p in self.panels.iter().rev() {
            match p.width {
                1 => self.backward::<1, 4>(p, x),
                2 => self.backward::<2, 2>(p, x),
                3 => self.backward::<3, 2>(p, x),
                _ => self.backward::<4, 2>(p, x),
            }
        }
    }

    /// A panel's first column, its triangle, the rows below it and their values.
    fn parts<const W: usize>(&self, p: &Panel) -> (usize, &[f64], &[u32], &[[f64; W]]) {
        let (r0, len, v0) = (p.rows as usize, p.len as usize, p.values as usize);
        let (triangle, below) = self.values[v0..].split_at(W * (W - 1) / 2);
        let below = &below.as_chunks::<W>().0[..len];
        (p.column as usize, triangle, &self.rows[r0..r0 + len], below)
    }

    /// L y = b on one panel: y_j = b_j / L_jj within the panel's triangle, then
    /// b_i −= Σ_b L_ib y_b for the rows i below it.
    fn forward<const W: usize>(&self, p: &Panel, x: &mut [f64]) {
        let (j, triangle, rows, below) = self.parts::<W>(p);
        let mut y = [0.0; W];
        let mut k = 0;
        for b in 0..W {
            let yb = x[j + b] * self.inv_diag[j + b];
            x[j + b] = yb;
            y[b] = yb;
            for a in b + 1..W {
                x[j + a] -= triangle[k] * yb;
                k += 1;
            }
        }
        for (&i, l) in rows.iter().zip(below) {
            let mut s = 0.0;
            for b in 0..W {
                s += l[b] * y[b];
            }
            x[i as usize] -= s;
        }
    }

    /// Lᵀ x = y on one panel: x_b = (y_b − Σ_{i>b} L_ib x_i) / L_bb, the sums over the rows
    /// below the panel gathered `R` rows at a time.
    fn backward<const W: usize, const R: usize>(&self, p: &Panel, x: &mut [f64]) {
        let (j, triangle, rows, below) = self.parts::<W>(p);
        let sums = gather::<W, R>(rows, |b, t| below[t][b], x);
        for b in (0..W).rev() {
            // The triangle's column b holds L_{j+a, j+b} for a > b, after the columns before.
            let first = b * (2 * W - b - 1) / 2;
            let mut v = x[j + b] - sums[b];
            for (a, l) in (b + 1..W).zip(&triangle[first..]) {
                v -= l * x[j + a];
            }
            x[j + b] = v * self.inv_diag[j + b];
        }
    }
}

/// Σ_t value(b, t) · x[rows[t]] for each of `W` columns sharing the row indices `rows`,
/// taking `R` rows at a time into independent partial sums (so that the adds do not wait
/// for each other): a row index and x_i are loaded once for the `W` columns. Inlined always:
/// as a call it measured 15 % slower in the solve.
#[inline(always)]
pub(super) fn gather<const W: usize, const R: usize>(
    rows: &[u32],
    value: impl Fn(usize, usize) -> f64,
    x: &[f64],
) -> [f64; W] {
    let mut sums = [[0.0; W]; R];
    let (chunks, rest) = rows.as_chunks::<R>();
    for (k, chunk) in chunks.iter().enumerate() {
        for ((r, &i), partial) in chunk.iter().enumerate().zip(&mut sums) {
            let xi = x[i as usize];
            for (b, s) in partial.iter_mut().enumerate() {
                *s += value(b, k * R + r) * xi;
            }
        }
    }
    let tail = chunks.len() * R;
    for (t, &i) in rest.iter().enumerate() {
        let xi = x[i as usize];
        for (b, s) in sums[0].iter_mut().enumerate() {
            *s += value(b, tail + t) * xi;
        }
    }
    std::array::from_fn(|b| sums.iter().map(|s| s[b]).sum())
}
