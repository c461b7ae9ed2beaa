// The C shim over Bullet's soft body for tryon-bench-bullet (see bullet_drape.h). Bullet's
// own example set-up (btSoftRigidDynamicsWorld, btSoftBodyHelpers::CreatePatch with shear
// diagonals, bending constraints of distance 2), with the drape scene's sizes and masses.
#include "bullet_drape.h"

#include <btBulletDynamicsCommon.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <cmath>
#include <cstdio>
#include <new>
#include <vector>

struct bullet_drape {
    btSoftBodyRigidBodyCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    btSphereShape sphere_shape{1.0f};
    btRigidBody *sphere = nullptr;
    btSoftBody *cloth = nullptr;
    std::vector<int> structural; // link indices
};

extern "C" bullet_drape *bullet_drape_create(const bullet_drape_desc *d, char *err, size_t err_size)
{
    if (d->side < 2 || !(d->side_m > 0) || !(d->mass_kg > 0) || d->iterations < 1) {
        std::snprintf(err, err_size, "bad drape description");
        return nullptr;
    }
    bullet_drape *b = new (std::nothrow) bullet_drape;
    if (!b) {
        std::snprintf(err, err_size, "out of memory");
        return nullptr;
    }
    try {
        b->world.setGravity(btVector3(0, -9.81f, 0));
        btSoftBodyWorldInfo &wi = b->world.getWorldInfo();
        wi.m_gravity = btVector3(0, -9.81f, 0);
        wi.air_density = 0;
        // The signed distance field Bullet collides soft bodies with is sampled on 0.25 m voxels
        // by default (objects of metres); the drape's sphere has a 0.25 m radius, so the field
        // is sampled at 2.5 mm, a tenth of the cloth's cell: fine enough not to be the error.
        wi.m_sparsesdf.Initialize(); // sets the default size: the finer one goes after it
        wi.m_sparsesdf.setDefaultVoxelsz(0.0025f);
        wi.m_sparsesdf.Reset();

        b->sphere_shape.setUnscaledRadius(d->sphere_r_m);
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, &b->sphere_shape);
        b->sphere = new btRigidBody(info);
        b->sphere->setFriction(1.0f);
        b->world.addRigidBody(b->sphere);

        float h = 0.5f * d->side_m, y = d->height_m;
        b->cloth = btSoftBodyHelpers::CreatePatch(wi, btVector3(-h, y, -h), btVector3(h, y, -h),
                                                  btVector3(-h, y, h), btVector3(h, y, h), d->side,
                                                  d->side, 0, true);
        btSoftBody::Material *m = b->cloth->appendMaterial();
        m->m_kLST = 1.0f; // as stiff as the solver makes it: Bullet's strongest cloth
        m->m_kAST = 1.0f;
        b->cloth->generateBendingConstraints(2, m);
        b->cloth->m_cfg.piterations = d->iterations;
        b->cloth->m_cfg.kDF = d->friction;
        b->cloth->m_cfg.collisions = btSoftBody::fCollision::SDF_RS;
        b->cloth->getCollisionShape()->setMargin(d->margin_m);
        b->cloth->setTotalMass(d->mass_kg);
        b->world.addSoftBody(b->cloth);

        float cell = d->side_m / (float)(d->side - 1);
        for (int i = 0; i < b->cloth->m_links.size(); i++) {
            const btSoftBody::Link &l = b->cloth->m_links[i];
            if (!l.m_bbending && std::fabs(l.m_rl - cell) < 0.01f * cell)
                b->structural.push_back(i);
        }
    } catch (const std::bad_alloc &) {
        std::snprintf(err, err_size, "out of memory");
        bullet_drape_destroy(b);
        return nullptr;
    }
    return b;
}

extern "C" void bullet_drape_destroy(bullet_drape *b)
{
    if (!b)
        return;
    if (b->cloth) {
        b->world.removeSoftBody(b->cloth);
        delete b->cloth;
    }
    if (b->sphere) {
        b->world.removeRigidBody(b->sphere);
        delete b->sphere;
    }
    b->world.getWorldInfo().m_sparsesdf.Reset();
    delete b;
}

extern "C" void bullet_drape_step(bullet_drape *b, float dt)
{
    b->world.stepSimulation(dt, 1, dt);
}

extern "C" int bullet_drape_node_count(const bullet_drape *b)
{
    return b->cloth->m_nodes.size();
}

extern "C" void bullet_drape_positions(const bullet_drape *b, float *xyz)
{
    for (int i = 0; i < b->cloth->m_nodes.size(); i++)
        for (int k = 0; k < 3; k++)
            xyz[3 * i + k] = b->cloth->m_nodes[i].m_x[k];
}

extern "C" int bullet_drape_structural_count(const bullet_drape *b)
{
    return (int)b->structural.size();
}

extern "C" void bullet_drape_structural(const bullet_drape *b, int32_t *ends, float *rest)
{
    const btSoftBody::Node *n0 = &b->cloth->m_nodes[0];
    for (size_t i = 0; i < b->structural.size(); i++) {
        const btSoftBody::Link &l = b->cloth->m_links[b->structural[i]];
        ends[2 * i] = (int32_t)(l.m_n[0] - n0);
        ends[2 * i + 1] = (int32_t)(l.m_n[1] - n0);
        rest[i] = l.m_rl;
    }
}

extern "C" const char *bullet_drape_version(void)
{
    static char v[32];
    std::snprintf(v, sizeof v, "Bullet %d.%02d", btGetVersion() / 100, btGetVersion() % 100);
    return v;
}
