/* metric_order.h — whether PSNR and FLIP rank a set of tiers alike: the
   report and the bench say it for every comparison they show.
   Usage:
       double psnr[3] = { 34.0, 31.2, 30.8 }, flip[3] = { 0.031, 0.044, 0.041 };
       metric_order o = metric_order_compare(psnr, flip, 3);
       // o.pairs 3, o.discordant 1 (tiers 1 and 2: PSNR says 1, FLIP says 2)
   A pair counts only when both metrics tell its two tiers apart (PSNR by
   more than METRIC_ORDER_PSNR_TIE dB, FLIP mean by more than
   METRIC_ORDER_FLIP_TIE): two images one metric calls equal have no
   order to disagree about. NaN values never count. */
#ifndef HT_EXAMPLES_METRIC_ORDER_H
#define HT_EXAMPLES_METRIC_ORDER_H

#define METRIC_ORDER_PSNR_TIE 0.05
#define METRIC_ORDER_FLIP_TIE 0.0005

typedef struct metric_order {
    int pairs;          /* pairs both metrics order */
    int discordant;     /* of those, the ones they order oppositely */
    int a, b;           /* the first discordant pair (-1 when none): PSNR ranks a above b, FLIP b above a */
} metric_order;

/* psnr: higher is closer; flip: lower is closer; n values each. */
metric_order metric_order_compare(const double *psnr, const double *flip, int n);

#endif
