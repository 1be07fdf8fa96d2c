// Loads the EARL profile and a model with Eclipse UML2 (standalone EMF, as Papyrus saves and
// reads them) and prints what tests/test_uml2.py asserts, one fact per line:
//   profile <name> defined=<true|false> errors=<n> warnings=<n>
//   model <name> errors=<n> warnings=<n>
//   load-error|load-warning <message>
//   earl-applications total=<n> resolved=<n>
//   unresolved <application type> <base id or '-'>
//   diagnostic <ERROR|WARNING> <qualified name of the element or '-'> | <message>
// Usage: java Uml2Check PROFILE MODEL
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;

import org.eclipse.emf.common.util.BasicDiagnostic;
import org.eclipse.emf.common.util.Diagnostic;
import org.eclipse.emf.common.util.URI;
import org.eclipse.emf.ecore.EObject;
import org.eclipse.emf.ecore.EPackage;
import org.eclipse.emf.ecore.resource.Resource;
import org.eclipse.emf.ecore.resource.ResourceSet;
import org.eclipse.emf.ecore.resource.impl.ResourceSetImpl;
import org.eclipse.emf.ecore.util.Diagnostician;
import org.eclipse.emf.ecore.util.EcoreUtil;
import org.eclipse.emf.ecore.xmi.XMLResource;
import org.eclipse.uml2.uml.Element;
import org.eclipse.uml2.uml.NamedElement;
import org.eclipse.uml2.uml.Package;
import org.eclipse.uml2.uml.Profile;
import org.eclipse.uml2.uml.UMLPackage;
import org.eclipse.uml2.uml.resources.util.UMLResourcesUtil;
import org.eclipse.uml2.uml.util.UMLUtil;

public final class Uml2Check {
    public static void main(String[] args) {
        ResourceSet resources = new ResourceSetImpl();
        UMLResourcesUtil.init(resources);
        Map<Object, Object> options = new HashMap<>();
        // elements of profiles that are not on the classpath (SysML) are kept as they are
        options.put(XMLResource.OPTION_RECORD_UNKNOWN_FEATURE, Boolean.TRUE);
        resources.getLoadOptions().putAll(options);

        Resource profileResource = load(resources, args[0]);
        Profile profile = (Profile) EcoreUtil.getObjectByType(profileResource.getContents(), UMLPackage.Literals.PROFILE);
        System.out.println("profile " + (profile == null ? "-" : profile.getName()) + " defined="
                + (profile != null && profile.isDefined()) + counts(profileResource));
        report(profileResource);

        Resource modelResource = load(resources, args[1]);
        Package model = (Package) EcoreUtil.getObjectByType(modelResource.getContents(), UMLPackage.Literals.PACKAGE);
        System.out.println("model " + (model == null ? "-" : model.getName()) + counts(modelResource));
        report(modelResource);

        EPackage definition = profile == null ? null : profile.getDefinition();
        String earlUri = definition == null ? "" : definition.getNsURI();
        int total = 0;
        int resolved = 0;
        for (EObject root : modelResource.getContents()) {
            if (root.eClass().getEPackage() == null || !earlUri.equals(root.eClass().getEPackage().getNsURI())) {
                continue;
            }
            total++;
            Element base = UMLUtil.getBaseElement(root);
            if (base != null && !base.eIsProxy() && UMLUtil.getStereotype(root) != null) {
                resolved++;
            } else {
                System.out.println("unresolved " + root.eClass().getName() + " " + (base == null ? "-" : EcoreUtil.getURI(base)));
            }
        }
        System.out.println("earl-applications total=" + total + " resolved=" + resolved);

        if (model != null) {
            Diagnostic result = Diagnostician.INSTANCE.validate(model);
            List<Diagnostic> leaves = new ArrayList<>();
            collect(result, leaves);
            for (Diagnostic d : leaves) {
                String where = "-";
                for (Object datum : d.getData()) {
                    if (datum instanceof NamedElement && ((NamedElement) datum).getQualifiedName() != null) {
                        where = ((NamedElement) datum).getQualifiedName();
                        break;
                    }
                }
                System.out.println("diagnostic " + severity(d) + " " + where + " | " + d.getMessage().replace('\n', ' '));
            }
        }
    }

    private static Resource load(ResourceSet resources, String path) {
        URI uri = URI.createFileURI(new java.io.File(path).getAbsolutePath());
        try {
            return resources.getResource(uri, true);
        } catch (RuntimeException error) {
            Resource resource = resources.getResource(uri, false);
            if (resource == null) {
                System.out.println("load-error " + error.getMessage());
                System.exit(2);
            }
            return resource;
        }
    }

    private static String counts(Resource resource) {
        return " errors=" + resource.getErrors().size() + " warnings=" + resource.getWarnings().size();
    }

    private static void report(Resource resource) {
        for (Resource.Diagnostic d : resource.getErrors()) {
            System.out.println("load-error " + d.getMessage().replace('\n', ' '));
        }
        for (Resource.Diagnostic d : resource.getWarnings()) {
            System.out.println("load-warning " + d.getMessage().replace('\n', ' '));
        }
    }

    private static void collect(Diagnostic diagnostic, List<Diagnostic> leaves) {
        if (diagnostic.getChildren().isEmpty()) {
            if (diagnostic.getSeverity() >= Diagnostic.WARNING) {
                leaves.add(diagnostic);
            }
            return;
        }
        for (Diagnostic child : diagnostic.getChildren()) {
            collect(child, leaves);
        }
    }

    private static String severity(Diagnostic d) {
        return d.getSeverity() >= Diagnostic.ERROR ? "ERROR" : "WARNING";
    }
}
