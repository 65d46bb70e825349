import mitsuba as mi, numpy as np
mi.set_variant('scalar_rgb')
h,w=64,128
v,u=np.mgrid[0:h,0:w]
img=np.zeros((h,w,3),np.float32)
img[...,0]=(u+0.5)/w            # red grows with u (phi)
img[...,1]=(v+0.5)/h            # green grows with v (theta, down)
img[...,2]=((u//16+v//16)%2)*0.5  # checker
img[5:12, 90:100]=[20,20,20]     # a bright patch
mi.Bitmap(img).write('env.exr')
xml='''<scene version="3.0.0">
 <integrator type="path"><integer name="max_depth" value="2"/></integrator>
 <sensor type="perspective"><float name="fov" value="100"/>
  <transform name="to_world"><lookat origin="0,0,0" target="%s" up="0,1,0"/></transform>
  <film type="hdrfilm"><integer name="width" value="96"/><integer name="height" value="64"/><rfilter type="box"/></film>
  <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
 </sensor>
 <emitter type="envmap"><string name="filename" value="env.exr"/>
  <transform name="to_world"><rotate y="1" angle="30"/><rotate x="1" angle="20"/></transform></emitter>
</scene>'''
for name,t in [('front','0,0,1'),('side','1,0.3,0'),('up','0.1,1,0.2')]:
    open(f'{name}.xml','w').write(xml%t)
    s=mi.load_file(f'{name}.xml'); im=mi.render(s); mi.Bitmap(im).write(f'{name}-mitsuba.exr')
print('ok')
