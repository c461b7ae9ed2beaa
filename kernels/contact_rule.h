/* The contact re-search's rule, declared once for the host and the OpenCL kernels (the host puts
 * it before collide.cl; sim/find_contacts.c includes it): sim_collider_research and its twin
 * sim_research_one in kernels/collide.cl. */
#ifndef TRYON_CONTACT_RULE_H
#define TRYON_CONTACT_RULE_H

/* How far a point may move from where its contact was searched before it is searched again.
 * clear: that search's clearance, the point's distance then to the nearest surface of all
 * (thickness + reach when nothing was within reach); h: the thickness. Moved less than clear - h,
 * no surface the search did not give it comes within h; a point resting within 2 h of its
 * triangle is searched again once it has slid h (the triangle's edge and vertex regions answer
 * for its neighbours that far). With clear in place of clear - h, the T-shirt's sleeves on
 * arms_down@1,0.5 went from 2.9 % to 8.5 % once the fast frames no longer searched every point
 * again every 10 steps (docs/sim-history-6.md, "Contacts searched again where a point moved"). */
static inline float sim_research_radius(float clear, float h)
{
    return clear > 2.0f * h ? clear - h : h;
}

#endif
