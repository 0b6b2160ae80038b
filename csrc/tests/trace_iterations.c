#include <stdio.h>
#include <math.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#include "tr_internal.h" /* reads the workspace's fields */
int main(int argc, char **argv){
  gsl_set_error_handler_off();
  double L=0.1, dd=1.04e-3, E=210e9, G=80e9, A=M_PI*dd*dd/4, I=M_PI*pow(dd,4)/64, EI=E*I, r=0.01;
  double rod[6]={L,EI,G*2*I,E*A,G*A,1}; double z3[3]={0,0,0};
  double td[24]; double EAt=50*3*EI/(r*r);
  /* locked displacements from a tension solve */
  for(int i=0;i<3;i++){double row[8]={r,2*M_PI*i/3,0,EAt,L,1,i==0?EI*M_PI/2/(r*L):0.0,0}; for(int j=0;j<8;j++) td[8*i+j]=row[j];}
  tr_options o=tr_default_options(); o.steps=3; char msg[512]; tr_model *m; tr_data *d;
  tr_model_alloc(&m, rod, td, 3, NULL, 0, z3, &o, msg, 512); d=tr_data_alloc(m,&o,11,NULL,msg,512);
  tr_solve(m,d,NULL,NULL); double q[3]; for(int i=0;i<3;i++) q[i]=d->displacement[i];
  printf("q = %g %g %g\n", q[0],q[1],q[2]);
  tr_data_free(d); tr_model_free(m);
  for(int i=0;i<3;i++){ td[8*i+5]=0; td[8*i+6]=q[i]; }
  double ld[7]={L,0,0.5,0,0,0,0};
  tr_model_alloc(&m, rod, td, 3, ld, 1, z3, &o, msg, 512); d=tr_data_alloc(m,&o,11,NULL,msg,512);
  d->steps=3; d->lam_act=d->lam_load=1;
  tr_solve_init(m,d,NULL,NULL);
  for(int it=0; it<30; it++){
    printf("it %2d |f| %.3e nfev %3d njev %d x=", it, d->fnorm, d->nfev, d->njev);
    for(int j=0;j<d->k;j++) printf(" %.4g", d->x[j]); printf("\n");
    if (d->fnorm < 1e-10) break;
    int st=tr_solve_iterate(m,d); if(st<0){printf("%s\n", d->message); break;}
  }
}
