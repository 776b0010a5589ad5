/* metric_order.c — see metric_order.h. */
#include "metric_order.h"

#include <math.h>

metric_order metric_order_compare(const double *psnr, const double *flip, int n) {
    metric_order o = { 0, 0, -1, -1 };
    for (int i = 0; i < n; i++) {
        for (int j = i + 1; j < n; j++) {
            const double dp = psnr[i] - psnr[j], df = flip[j] - flip[i]; /* > 0: i closer */
            if (isnan(dp) || isnan(df) || fabs(dp) <= METRIC_ORDER_PSNR_TIE || fabs(df) <= METRIC_ORDER_FLIP_TIE)
                continue;
            o.pairs++;
            if ((dp > 0) == (df > 0)) continue;
            if (o.discordant++ == 0) o.a = dp > 0 ? i : j, o.b = dp > 0 ? j : i;
        }
    }
    return o;
}
