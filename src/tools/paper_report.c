/* paper_report.c — `firmness_model paper`'s DIR/paper.md: the claims'
 * rows per profile, the figures, and the designer (design.h) on the shipped
 * cultivar against the paper's optimum. */
#define _POSIX_C_SOURCE 200809L
#include "paper.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli_flags.h"
#include "closeout.h"
#include "design.h"
#include "impact.h"
#include "model.h"
#include "model_table.h"
#include "options.h"
#include "plot.h"
#include "lamb.h"
#include "spectrum.h"
#include "text.h"
#include "paper_work.h"

/* The shipped cultivar, in the package's config/ (AF_CONFIG_DIR). */
#define AF_PAPER_CULTIVAR "jonagold.yaml"

/* The designer (design.h) on the shipped cultivar: its report quoted as
 * `firmness_model design` prints it (the cultivar shown relative to the
 * package), then the verdict from the same result. 0, or 1 when the
 * designer or the paper's optimum fails (said on stderr). */
static int design_section(FILE *md)
{
  static af_design_result r;
  af_design_args a = af_design_args_default();
  a.cultivar = AF_CONFIG_DIR "/" AF_PAPER_CULTIVAR;
  const char *shown = "config/" AF_PAPER_CULTIVAR;
  char err[1100];
  bool bad_input = false;
  if (af_design_execute(&a, &r, &bad_input, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model paper: design: %s\n", err);
    return 1;
  }
  fprintf(md, "```\n$ firmness_model design --cultivar %s\n", shown);
  af_design_print(md, shown, &a, &r);
  fprintf(md, "```\n\n");
  if (r.paper_status != AF_OK) {
    fprintf(stderr,
            "firmness_model paper: design: the paper's optimum could not be evaluated: %s\n",
            af_strerror(r.paper_status));
    return 1;
  }
  fprintf(md,
          "Verdict: on the cultivar's domain (E2 and mass over the YAML's ranges, R2 from the "
          "equator down to %.0f mm) under the shipped profile, the paper's optimum (%.0f g, %.1f "
          "m/s) **gives up %d of %d apples**; the designer's recommendation gives up %d. The "
          "paper's optimum was derived for the average apple at R2 40 mm; the domain here adds "
          "light firm apples (0S2 above the main lobe's band) and R2 down to %.0f mm (shear over "
          "the yield), which a lighter, slower hammer handles (shorter pulse, wider band, lower "
          "shear).\n\n",
          a.r2_min * 1e3, r.paper.hammer_mass_kg * 1e3, r.paper.velocity_m_s, r.paper.failed,
          AF_DESIGN_APPLES, r.recommended.failed, a.r2_min * 1e3);
  return 0;
}

int af_paper_write_report(af_paper *w, af_claim_row rows[][2])
{
  char path[640];
  af_text(path, sizeof path, "%s/paper.md", w->out_dir);
  FILE *md = fopen(path, "w");
  if (!md) {
    fprintf(stderr, "firmness_model paper: cannot write %s: %s\n", path, strerror(errno));
    return 1;
  }
  const af_model_params t = af_paper_profile(1); /* the table's figures, printed not typed */
  fprintf(md,
          "# The paper reproduced\n\n"
          "Written by `firmness_model paper%s` (src/tools/paper.c); every number below is "
          "computed by it (ODE path), none is typed in. Regenerate with `firmness_model paper "
          "--out doc`.\n\n"
          "Paper: Chen & De Baerdemaeker, *Influence of the apple properties on reliability of "
          "impact excitation in frequency measurements of apples*. The strike is the paper's "
          "optimum (%g g flat rigid hammer at %g m/s) on the average apple (%g MPa, %g g, R2 "
          "%g mm, e %g, ν2 %g, %g kg/m³) unless a claim varies something. Two profiles "
          "(PHYSICS.md §7):\n\n"
          "- **paper-literal** (`--profile paper`): Lankarani–Nikravesh damping as printed, the "
          "second lobe, the power-half (−3 dB) band, τ_max = 0.31 p0;\n"
          "- **shipped default**: exact damping for the asked e, the main lobe, the "
          "amplitude-half (−6 dB) band, τ_max/p0 exact for ν2.\n\n"
          "Both use the shipped yield law τ_y = %g × %g MPa × (E2/%g MPa)^%.2f (a calibration "
          "on the shipped profile; doc/model.md, \"The yield law\") and Lamb's 0S2 of a "
          "homogeneous sphere (modulus factor 1) where the paper used a finite-element model. "
          "Verdicts: *reproduces*, *reproduces with a different number*, *does not reproduce*, "
          "and *calibrated to 31 mm* where a calibration put the figure there (the yield law's "
          "reference is the average apple's shear at R2 31 mm, so agreeing on 31 mm tests "
          "nothing).\n\n",
          w->quick ? " --quick" : "", t.impact.hammer_mass_kg * 1e3, t.impact.velocity_m_s,
          t.impact.fruit_modulus_pa * 1e-6, t.fruit_mass_kg * 1e3, t.impact.strike_radius_m * 1e3,
          t.impact.restitution, t.impact.fruit_poisson, t.fruit_density_kg_m3, t.yield_ratio,
          t.yield_reference_modulus_pa * 1e-6, t.yield_reference_modulus_pa * 1e-6,
          t.yield_exponent);
  fprintf(
      md,
      "## Verdicts at a glance\n\n| claim | paper-literal | shipped default |\n|---|---|---|\n");
  for (size_t c = 0; c < AF_PAPER_N_CLAIMS; c++)
    fprintf(md, "| %s | %s | %s |\n", af_paper_claims[c].claim,
            af_paper_verdict_name[rows[c][0].verdict], af_paper_verdict_name[rows[c][1].verdict]);
  fprintf(md, "\n## The claims\n\n");
  for (size_t c = 0; c < AF_PAPER_N_CLAIMS; c++) {
    fprintf(md, "### %zu. %s\n\nThe paper: %s. Figures: %s.\n\n", c + 1, af_paper_claims[c].claim,
            af_paper_claims[c].paper_says, af_paper_claims[c].figs);
    fprintf(md, "| profile | the project's figure | verdict | why |\n|---|---|---|---|\n");
    for (int k = 0; k < 2; k++)
      fprintf(md, "| %s | %s | **%s** | %s |\n", af_paper_profile_title[k], rows[c][k].figure,
              af_paper_verdict_name[rows[c][k].verdict], rows[c][k].why);
    fprintf(md, "\n");
  }
  fprintf(md, "## The figures\n\nEach under both profiles (PNG here, SVG beside it in "
              "doc/paper/).\n\n");
  static const char *const caption[] = {
      NULL,
      NULL,
      "Fig. 2: E2 2, 4, 8, 12 MPa — pulse and spectrum",
      "Fig. 3: E2 — the half-power range against the 0S2 of 100 g and 250 g; shear against "
      "yield",
      "Fig. 4: R2 10, 20, 31, 40, 60 mm — pulse and spectrum",
      "Fig. 5: R2 — the half-power range against the 0S2; shear against yield",
      "Fig. 6: e 1.0, 0.9, 0.8, 0.6, 0.4 — pulse and spectrum",
      "Fig. 7: e — the half-power range against the 0S2; shear against yield",
      "Fig. 8: ν2 0.2, 0.3, 0.4, 0.49 — pulse and spectrum",
  };
  for (int fig = 2; fig <= 8; fig++) {
    fprintf(md, "### %s\n\n", caption[fig]);
    for (int k = 0; k < 2; k++)
      fprintf(md, "![Fig. %d analogue, %s profile](paper/fig%d_%s.png)\n\n", fig,
              af_paper_profile_title[k], fig, af_paper_profile_key[k]);
  }
  fprintf(md, "## The designer against the paper's optimum\n\n");
  int rc = design_section(md);
  if (af_closeout_file(md, path) != 0)
    rc = 1;
  if (rc == 0)
    af_options_wrote(path);
  return rc;
}
